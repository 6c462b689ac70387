#include "unjam/io/json_lines.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "unjam/io/packing_file.hpp"
#include "unjam/io/read_text.hpp"

namespace unjam {

nlohmann::json NumberOrNull(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

double NumberOrNaN(const nlohmann::json& j) { return j.is_null() ? std::nan("") : j.get<double>(); }

namespace {

// The lines of `text`, read from `path` (named in errors).
JsonLines ParseJsonLines(const std::string& text, const std::filesystem::path& path) {
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

}  // namespace

JsonLines ReadJsonLines(const std::filesystem::path& path) {
  return ParseJsonLines(ReadInputText(path), path);
}

bool HasHeaderLine(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string first;
  return static_cast<bool>(std::getline(in, first)) && !in.eof();
}

std::ofstream AppendTo(const std::filesystem::path& path, const nlohmann::json& header) {
  const bool fresh = !HasHeaderLine(path);
  std::ofstream out(path,
                    fresh ? std::ios::trunc | std::ios::binary : std::ios::app | std::ios::binary);
  if (!out) throw OutputError(path.string() + ": cannot open for writing");
  if (fresh) out << header.dump() << '\n' << std::flush;
  return out;
}

void RequireHeader(const std::filesystem::path& path, const nlohmann::json& found,
                   const nlohmann::json& expected, const std::string& remedy) {
  if (found == expected) return;
  std::string keys;
  for (const auto& [key, value] : expected.items()) {
    if (!found.contains(key) || found[key] != value) keys += (keys.empty() ? "" : ", ") + key;
  }
  for (const auto& [key, value] : found.items()) {
    if (!expected.contains(key)) keys += (keys.empty() ? "" : ", ") + key;
  }
  throw std::invalid_argument(path.string() + " holds a run with other parameters (" + keys +
                              "): " + remedy);
}

std::filesystem::path RankPath(const std::filesystem::path& path, int rank) {
  if (rank == 0) return path;
  return path.parent_path() /
         (path.stem().string() + ".rank" + std::to_string(rank) + path.extension().string());
}

namespace {

// The files named as rank files of `path` (X.rank<r>.jsonl beside X.jsonl), sorted by name.
std::vector<std::filesystem::path> RankNamed(const std::filesystem::path& path) {
  const std::string prefix = path.stem().string() + ".rank", suffix = path.extension().string();
  const std::filesystem::path dir =
      path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  std::vector<std::filesystem::path> ranks;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > prefix.size() + suffix.size() && name.rfind(prefix, 0) == 0 &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      ranks.push_back(path.parent_path() / name);
    }
  }
  std::sort(ranks.begin(), ranks.end());
  return ranks;
}

}  // namespace

std::vector<std::filesystem::path> RankFiles(const std::filesystem::path& path) {
  std::vector<std::filesystem::path> files;
  if (HasHeaderLine(path)) files.push_back(path);
  for (const std::filesystem::path& rank : RankNamed(path)) {
    if (HasHeaderLine(rank)) files.push_back(rank);
  }
  return files;
}

void MergeRankFiles(const std::filesystem::path& path, const nlohmann::json& header,
                    const std::string& remedy) {
  for (const std::filesystem::path& from : RankNamed(path)) {
    if (!HasHeaderLine(from)) {  // a rank that ended before its header: nothing to merge
      std::filesystem::remove(from);
      continue;
    }
    std::string text = ReadInputText(from);
    const JsonLines file = ParseJsonLines(text, from);
    RequireHeader(from, file.header, header, remedy);
    text.resize(static_cast<std::size_t>(file.valid_bytes));
    const std::size_t body = text.find('\n') + 1;  // after the header line
    std::ofstream out(path, std::ios::app | std::ios::binary);
    out << text.substr(body) << std::flush;
    if (!out) throw OutputError(path.string() + ": cannot append the records of " + from.string());
    out.close();
    std::filesystem::remove(from);
  }
}

}  // namespace unjam
