#include "unjam/io/study_config.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "unjam/io/packing_file.hpp"
#include "unjam/io/read_text.hpp"

namespace unjam {

namespace {

using Json = nlohmann::json;

// "[k]": a list element in a key path. Built by appends: GCC 12 warns (-Wrestrict, a false
// positive) on "[" + std::to_string(k) + "]".
std::string IndexKey(std::size_t k) {
  std::string key = "[";
  key += std::to_string(k);
  key += ']';
  return key;
}

// A key's place for messages: its dotted path, and the line where it is written.
class ConfigReader {
 public:
  ConfigReader(std::string file, std::string text)
      : file_(std::move(file)), text_(std::move(text)) {}

  [[noreturn]] void Fail(const std::vector<std::string>& path, const std::string& what) const {
    std::string dotted;
    for (const std::string& p : path) dotted += (dotted.empty() || p[0] == '[' ? "" : ".") + p;
    throw InputError(file_, LineOf(path), dotted.empty() ? what : dotted + ": " + what);
  }

  // The line of the path's last key, found by looking for each key's quoted name after the
  // previous one's (0 if not found: a key brought in by a size variant).
  int LineOf(const std::vector<std::string>& path) const {
    std::size_t at = 0;
    for (const std::string& key : path) {
      if (key.empty() || key[0] == '[') continue;
      const std::size_t next = text_.find("\"" + key + "\"", at);
      if (next == std::string::npos) return 0;
      at = next;
    }
    return at == 0 && path.empty()
               ? 0
               : 1 + static_cast<int>(std::count(
                         text_.begin(), text_.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  }

  void OnlyKeys(const Json& object, const std::vector<std::string>& path,
                const std::set<std::string>& allowed) const {
    if (!object.is_object()) Fail(path, "must be an object");
    for (const auto& [key, value] : object.items()) {
      if (allowed.count(key) == 0) {
        std::string names;
        for (const std::string& a : allowed) names += (names.empty() ? "" : ", ") + a;
        Fail(Append(path, key), "unknown key (expected one of: " + names + ")");
      }
    }
  }

  double Number(const Json& j, const std::vector<std::string>& path, double lowest,
                bool inclusive) const {
    if (!j.is_number()) Fail(path, "must be a number");
    const double x = j.get<double>();
    if (!std::isfinite(x) || (inclusive ? x < lowest : x <= lowest))
      Fail(path, "must be a number " + std::string(inclusive ? ">= " : "> ") + Json(lowest).dump() +
                     ", got " + j.dump());
    return x;
  }

  int Integer(const Json& j, const std::vector<std::string>& path, int lowest) const {
    if (!j.is_number_integer() || j.get<long long>() < lowest || j.get<long long>() > 1000000000)
      Fail(path, "must be an integer >= " + std::to_string(lowest) + ", got " + j.dump());
    return j.get<int>();
  }

  std::vector<double> Frictions(const Json& j, const std::vector<std::string>& path) const {
    if (!j.is_array() || j.empty()) Fail(path, "must be a non-empty list of numbers >= 0");
    std::vector<double> out;
    for (std::size_t k = 0; k < j.size(); ++k)
      out.push_back(Number(j[k], Append(path, IndexKey(k)), 0.0, true));
    return out;
  }

  std::vector<std::uint64_t> Seeds(const Json& j, const std::vector<std::string>& path) const {
    if (!j.is_array() || j.empty()) Fail(path, "must be a non-empty list of integers >= 0");
    std::vector<std::uint64_t> out;
    for (std::size_t k = 0; k < j.size(); ++k) {
      if (!j[k].is_number_unsigned())
        Fail(Append(path, IndexKey(k)), "must be an integer >= 0, got " + j[k].dump());
      out.push_back(j[k].get<std::uint64_t>());
    }
    return out;
  }

  std::vector<std::string> Names(const Json& j, const std::vector<std::string>& path,
                                 const std::set<std::string>& allowed) const {
    if (!j.is_array() || j.empty()) Fail(path, "must be a non-empty list of names");
    std::vector<std::string> out;
    for (std::size_t k = 0; k < j.size(); ++k) {
      if (!j[k].is_string() || allowed.count(j[k].get<std::string>()) == 0) {
        std::string names;
        for (const std::string& a : allowed) names += (names.empty() ? "" : ", ") + a;
        Fail(Append(path, IndexKey(k)), "must be one of " + names + ", got " + j[k].dump());
      }
      out.push_back(j[k].get<std::string>());
    }
    return out;
  }

  bool Boolean(const Json& j, const std::vector<std::string>& path) const {
    if (!j.is_boolean()) Fail(path, "must be true or false");
    return j.get<bool>();
  }

  static std::vector<std::string> Append(std::vector<std::string> path, const std::string& key) {
    path.push_back(key);
    return path;
  }

 private:
  std::string file_, text_;
};

// One set or a list of them.
std::vector<std::pair<Json, std::vector<std::string>>> Sets(const ConfigReader& r, const Json& j,
                                                            const std::string& name) {
  std::vector<std::pair<Json, std::vector<std::string>>> out;
  if (j.is_object()) {
    out.emplace_back(j, std::vector<std::string>{name});
  } else if (j.is_array()) {
    for (std::size_t k = 0; k < j.size(); ++k)
      out.emplace_back(j[k], std::vector<std::string>{name, IndexKey(k)});
  } else {
    r.Fail({name}, "must be an object or a list of objects");
  }
  return out;
}

PressureSet ReadPressureSet(const ConfigReader& r, const Json& j,
                            const std::vector<std::string>& at) {
  r.OnlyKeys(j, at, {"n", "pressure", "mu", "seeds", "openings", "modes", "bounds", "max_steps"});
  for (const char* key : {"mu", "seeds", "openings"})
    if (!j.contains(key)) r.Fail(at, std::string("needs \"") + key + "\"");
  auto key = [&](const char* k) { return ConfigReader::Append(at, k); };
  PressureSet s;
  if (j.contains("n")) s.n = r.Integer(j["n"], key("n"), 2);
  if (j.contains("pressure")) s.pressure = r.Number(j["pressure"], key("pressure"), 0.0, false);
  s.mu = r.Frictions(j["mu"], key("mu"));
  s.seeds = r.Seeds(j["seeds"], key("seeds"));
  s.openings = r.Integer(j["openings"], key("openings"), 1);
  if (j.contains("modes"))
    s.modes = r.Names(j["modes"], key("modes"), {"fixed-pressure", "fixed-volume"});
  if (j.contains("bounds")) s.bounds = r.Boolean(j["bounds"], key("bounds"));
  if (j.contains("max_steps")) s.max_steps = r.Integer(j["max_steps"], key("max_steps"), 1);
  return s;
}

GravitySet ReadGravitySet(const ConfigReader& r, const Json& j,
                          const std::vector<std::string>& at) {
  r.OnlyKeys(j, at, {"n", "width", "mu", "seeds", "shifts", "bounds", "max_steps"});
  for (const char* key : {"mu", "seeds"})
    if (!j.contains(key)) r.Fail(at, std::string("needs \"") + key + "\"");
  auto key = [&](const char* k) { return ConfigReader::Append(at, k); };
  GravitySet s;
  if (j.contains("n")) s.n = r.Integer(j["n"], key("n"), 1);
  if (j.contains("width")) s.width = r.Number(j["width"], key("width"), 0.0, false);
  s.mu = r.Frictions(j["mu"], key("mu"));
  s.seeds = r.Seeds(j["seeds"], key("seeds"));
  if (j.contains("shifts")) s.sides = r.Names(j["shifts"], key("shifts"), {"top", "bottom"});
  if (j.contains("bounds")) s.bounds = r.Boolean(j["bounds"], key("bounds"));
  if (j.contains("max_steps")) s.max_steps = r.Integer(j["max_steps"], key("max_steps"), 1);
  return s;
}

Json Parse(const std::string& file, const std::string& text) {
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    const std::size_t at = std::min<std::size_t>(e.byte, text.size());
    const int line = 1 + static_cast<int>(std::count(
                             text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
    throw InputError(file, line, std::string("not valid JSON: ") + e.what());
  }
}

Json ApplySize(const ConfigReader& r, Json config, const std::string& size) {
  Json sizes = config.contains("sizes") ? config["sizes"] : Json::object();
  config.erase("sizes");
  if (!sizes.is_object()) r.Fail({"sizes"}, "must be an object of named variants");
  if (size.empty()) return config;
  if (!sizes.contains(size)) {
    std::string names;
    for (const auto& [name, v] : sizes.items()) names += (names.empty() ? "" : ", ") + name;
    r.Fail({"sizes"}, "has no size \"" + size +
                          "\" (--size); it has: " + (names.empty() ? std::string("none") : names));
  }
  config.merge_patch(sizes[size]);
  return config;
}

}  // namespace

StudyConfig ReadStudyConfig(const std::filesystem::path& path, const std::string& size) {
  const std::string file = path.string();
  const std::string text = ReadInputText(path);
  const ConfigReader r(file, text);
  Json config = Parse(file, text);
  if (!config.is_object()) r.Fail({}, "must hold one JSON object");
  r.OnlyKeys(config, {},
             {"description", "output", "packings", "threads", "pressure", "gravity", "sizes"});
  StudyConfig out;
  out.file = file;
  out.size = size;
  config = ApplySize(r, config, size);
  r.OnlyKeys(config, {}, {"description", "output", "packings", "threads", "pressure", "gravity"});
  if (config.contains("description")) {
    if (!config["description"].is_string()) r.Fail({"description"}, "must be a string");
    out.description = config["description"].get<std::string>();
  }
  if (config.contains("output")) {
    if (!config["output"].is_string() || config["output"].get<std::string>().empty())
      r.Fail({"output"}, "must be a folder name");
    out.output = config["output"].get<std::string>();
  }
  if (config.contains("packings")) {
    if (!config["packings"].is_string() || config["packings"].get<std::string>().empty())
      r.Fail({"packings"}, "must be a folder name");
    out.packings = config["packings"].get<std::string>();
  }
  if (config.contains("threads")) out.threads = r.Integer(config["threads"], {"threads"}, 0);
  if (config.contains("pressure"))
    for (const auto& [set, at] : Sets(r, config["pressure"], "pressure"))
      out.pressure.push_back(ReadPressureSet(r, set, at));
  if (config.contains("gravity"))
    for (const auto& [set, at] : Sets(r, config["gravity"], "gravity"))
      out.gravity.push_back(ReadGravitySet(r, set, at));
  if (out.pressure.empty() && out.gravity.empty())
    r.Fail({}, "names no packings: give \"pressure\" or \"gravity\" sets");
  out.resolved = config;
  return out;
}

}  // namespace unjam
