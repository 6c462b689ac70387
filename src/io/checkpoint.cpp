#include "unjam/io/checkpoint.hpp"

#include <limits>

#include "unjam/io/packing_file.hpp"

namespace unjam {

namespace {
constexpr const char* kFormat = "unjam-checkpoint";
constexpr int kVersion = 1;
nlohmann::json WarmStartJson(const std::vector<ContactForce>& impulses) {
  nlohmann::json rows = nlohmann::json::array();
  for (const ContactForce& f : impulses)
    rows.push_back({f.i, f.j, f.image[0], f.image[1], f.normal, f.tangential});
  return rows;
}

std::vector<ContactForce> WarmStartFromJson(const nlohmann::json& rows, const std::string& name,
                                            const Scene& scene) {
  const int particles = static_cast<int>(scene.particles.size());
  const int walls = static_cast<int>(scene.cell.walls.size());
  std::vector<ContactForce> out;
  for (const nlohmann::json& r : rows) {
    const bool ok = r.is_array() && r.size() == 6 && r[0].is_number_integer() &&
                    r[1].is_number_integer() && r[2].is_number_integer() &&
                    r[3].is_number_integer() && r[4].is_number() && r[5].is_number();
    if (!ok) throw InputError(name, 0, "malformed warm-start entry " + r.dump());
    ContactForce f{r[0].get<int>(),
                   r[1].get<int>(),
                   {r[2].get<int>(), r[3].get<int>()},
                   r[4].get<double>(),
                   r[5].get<double>()};
    const bool j_ok = IsWallIndex(f.j) ? JToWallIndex(f.j) < walls : f.j < particles;
    if (f.i < 0 || f.i >= particles || !j_ok) {
      throw InputError(name, 0,
                       "warm-start entry names a particle that does not exist: " + r.dump());
    }
    out.push_back(f);
  }
  return out;
}

}  // namespace

std::string FormatCheckpoint(const Checkpoint& c) {
  const nlohmann::json j = {{"format", kFormat},
                            {"version", kVersion},
                            {"parameters", c.parameters},
                            {"progress", c.progress},
                            {"packing", FormatPacking(c.scene)},
                            {"warm_start", WarmStartJson(c.warm_start)}};
  return j.dump(1) + "\n";
}

Checkpoint ParseCheckpoint(std::string_view text, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(name, 0, std::string("not a checkpoint (JSON: ") + e.what() + ")");
  }
  auto require = [&](const char* key, nlohmann::json::value_t type) -> const nlohmann::json& {
    if (!j.is_object() || !j.contains(key) || j[key].type() != type) {
      throw InputError(name, 0,
                       std::string("not a checkpoint: missing or malformed \"") + key + "\"");
    }
    return j[key];
  };
  if (require("format", nlohmann::json::value_t::string) != kFormat) {
    throw InputError(name, 0, "not a checkpoint: format is not \"unjam-checkpoint\"");
  }
  const nlohmann::json& version = j.contains("version") ? j["version"] : nlohmann::json();
  if (!version.is_number_integer() || version.get<int>() != kVersion) {
    throw InputError(name, 0, "unsupported checkpoint version " + version.dump());
  }
  Checkpoint c;
  c.parameters = require("parameters", nlohmann::json::value_t::object);
  c.progress = require("progress", nlohmann::json::value_t::object);
  // A state in the middle of the dynamics may overlap more than a saved packing may.
  ReadOptions read;
  read.overlap_tolerance = std::numeric_limits<double>::infinity();
  c.scene = ParsePacking(require("packing", nlohmann::json::value_t::string).get<std::string>(),
                         name + " (packing)", read);
  c.warm_start =
      WarmStartFromJson(require("warm_start", nlohmann::json::value_t::array), name, c.scene);
  return c;
}

}  // namespace unjam
