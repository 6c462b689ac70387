#include "unjam/io/json_lines.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "unjam/io/packing_file.hpp"

namespace unjam {

JsonLines ReadJsonLines(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), 0, "cannot open for reading");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  JsonLines out;
  std::size_t begin = 0;
  int line = 0;
  while (begin < text.size()) {
    const std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) break;  // torn last line: ignored
    ++line;
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text.substr(begin, end - begin));
    } catch (const nlohmann::json::exception& e) {
      throw InputError(path.string(), line, std::string("not a JSON object: ") + e.what());
    }
    if (!j.is_object()) throw InputError(path.string(), line, "not a JSON object");
    if (line == 1) {
      out.header = std::move(j);
    } else {
      out.lines.emplace_back(line, std::move(j));
    }
    begin = end + 1;
  }
  out.valid_bytes = begin;
  if (line == 0) throw InputError(path.string(), 1, "empty records file (no header line)");
  return out;
}

void RequireHeader(const std::filesystem::path& path, const nlohmann::json& found, const nlohmann::json& expected,
                   const std::string& remedy) {
  if (found == expected) return;
  std::string keys;
  for (const auto& [key, value] : expected.items()) {
    if (!found.contains(key) || found[key] != value) keys += (keys.empty() ? "" : ", ") + key;
  }
  for (const auto& [key, value] : found.items()) {
    if (!expected.contains(key)) keys += (keys.empty() ? "" : ", ") + key;
  }
  throw std::invalid_argument(path.string() + " holds a run with other parameters (" + keys + "): " + remedy);
}

}  // namespace unjam
