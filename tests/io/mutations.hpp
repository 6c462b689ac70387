// Seeded corruptions of valid text files for the reader tests: byte flips, truncations,
// deleted and duplicated lines, hostile numbers, inserted bytes.
#pragma once

#include <random>
#include <string>
#include <vector>

namespace unjam::testing {

inline std::vector<std::string> SplitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t nl = text.find('\n', pos);
    const std::size_t end = nl == std::string::npos ? text.size() : nl + 1;
    lines.push_back(text.substr(pos, end - pos));
    pos = end;
  }
  return lines;
}

inline std::string JoinLines(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line;
  return text;
}

// Replaces one whitespace-separated token with a hostile or plausible value.
inline std::string ReplaceToken(const std::string& text, std::mt19937_64& rng) {
  static const char* kValues[] = {
      "nan",        "-inf",        "1e400",  "1e-400",    "-1",
      "0",          "-0",          "1.0abc", "",          "99999999999999999999",
      "2147483648", "-2147483649", "1",      "2",         "0.30000000000000004",
      "5e-324",     "#",           "end",    "particles", "+",
      "."};
  std::vector<std::size_t> starts;
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (text[k] != ' ' && text[k] != '\n' && (k == 0 || text[k - 1] == ' ' || text[k - 1] == '\n'))
      starts.push_back(k);
  }
  if (starts.empty()) return text;
  const std::size_t start = starts[rng() % starts.size()];
  std::size_t end = start;
  while (end < text.size() && text[end] != ' ' && text[end] != '\n') ++end;
  std::string value = kValues[rng() % std::size(kValues)];
  if (rng() % 4 == 0) value = std::to_string(static_cast<long long>(rng() % 2000) - 1000);
  return text.substr(0, start) + value + text.substr(end);
}

inline std::string Mutate(std::string text, std::mt19937_64& rng) {
  const int mutations = 1 + static_cast<int>(rng() % 3);
  for (int m = 0; m < mutations && !text.empty(); ++m) {
    switch (rng() % 6) {
      case 0:  // flip a byte to any value, NUL and non-ASCII included
        text[rng() % text.size()] = static_cast<char>(rng() % 256);
        break;
      case 1:  // truncate
        text.resize(rng() % text.size());
        break;
      case 2: {  // delete a line
        std::vector<std::string> lines = SplitLines(text);
        lines.erase(lines.begin() + static_cast<long>(rng() % lines.size()));
        text = JoinLines(lines);
        break;
      }
      case 3: {  // duplicate a line
        std::vector<std::string> lines = SplitLines(text);
        const std::size_t k = rng() % lines.size();
        lines.insert(lines.begin() + static_cast<long>(k), lines[k]);
        text = JoinLines(lines);
        break;
      }
      case 4: text = ReplaceToken(text, rng); break;
      default:  // insert random bytes
        text.insert(rng() % text.size(),
                    std::string(1 + rng() % 8, static_cast<char>(rng() % 256)));
        break;
    }
  }
  return text;
}

}  // namespace unjam::testing
