#include "unjam/io/response_records.hpp"

#include <fstream>
#include <optional>
#include <sstream>

#include "unjam/io/json_lines.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {

namespace {
// Empty profile bins, and the linearity check's fields when not checked, are written as null
// (NumberOrNull, json_lines.hpp).
nlohmann::json WithNulls(const std::vector<double>& v) {
  nlohmann::json out = nlohmann::json::array();
  for (double x : v) out.push_back(NumberOrNull(x));
  return out;
}

std::vector<double> FromNulls(const nlohmann::json& j) {
  std::vector<double> out;
  for (const auto& x : j) out.push_back(NumberOrNaN(x));
  return out;
}

nlohmann::json TargetJson(const PerturbationTarget& t) {
  const bool shift = t.kind == PerturbationTarget::Kind::kParticleShift;
  return {{"kind", shift ? "shift" : "opening"},
          {"i", t.i},
          {"j", t.j},
          {"image", t.image},
          {"direction", {t.direction.x(), t.direction.y()}}};
}

PerturbationTarget TargetFromJson(const nlohmann::json& j) {
  PerturbationTarget t;
  t.kind = j.at("kind").get<std::string>() == "shift" ? PerturbationTarget::Kind::kParticleShift
                                                      : PerturbationTarget::Kind::kContactOpening;
  t.i = j.at("i").get<int>();
  t.j = j.at("j").get<int>();
  t.image = j.at("image").get<std::array<int, 2>>();
  t.direction = Vec2(j.at("direction")[0].get<double>(), j.at("direction")[1].get<double>());
  return t;
}
}  // namespace

nlohmann::json ToJson(const ReducedResponse& r) {
  return {{"target", TargetJson(r.target)},
          {"origin", {r.origin.x(), r.origin.y()}},
          {"axis", {r.axis.x(), r.axis.y()}},
          {"f_crit", r.f_crit},
          {"f_reference", r.f_reference},
          {"penetration_depth", r.penetration_depth},
          {"cell_strain", r.cell_strain},
          {"pressure_change", r.pressure_change},
          {"inertia_ratio", r.inertia_ratio},
          {"inertial_force", r.inertial_force},
          {"fcrit_10xi", NumberOrNull(r.fcrit_10xi)},
          {"linearity_misfit", NumberOrNull(r.linearity_misfit)},
          {"equilibrium_residual", r.equilibrium_residual},
          {"residual", r.residual},
          {"seconds", r.seconds},
          {"iterations", r.iterations},
          {"status", ToString(r.status)},
          {"message", r.message},
          {"backend", r.backend},
          {"rattler", r.rattler},
          {"displacement_profile", WithNulls(r.displacement_profile)},
          {"force_profile", WithNulls(r.force_profile)},
          {"field", r.field},
          {"field_count", r.field_count},
          {"stress", r.stress}};
}

ReducedResponse ReducedResponseFromJson(const nlohmann::json& j, const std::string& where) {
  try {
    ReducedResponse r;
    r.target = TargetFromJson(j.at("target"));
    r.origin = Vec2(j.at("origin")[0].get<double>(), j.at("origin")[1].get<double>());
    r.axis = Vec2(j.at("axis")[0].get<double>(), j.at("axis")[1].get<double>());
    r.f_crit = NumberOrNaN(j.at("f_crit"));  // null: blocked
    r.f_reference = j.at("f_reference").get<double>();
    r.penetration_depth = j.at("penetration_depth").get<double>();
    r.cell_strain = j.at("cell_strain").get<double>();
    r.pressure_change = j.at("pressure_change").get<double>();
    r.inertia_ratio = j.at("inertia_ratio").get<double>();
    r.inertial_force = NumberOrNaN(j.at("inertial_force"));
    r.fcrit_10xi = NumberOrNaN(j.at("fcrit_10xi"));  // null: not checked
    r.linearity_misfit = NumberOrNaN(j.at("linearity_misfit"));
    r.equilibrium_residual = j.at("equilibrium_residual").get<double>();
    r.residual = j.at("residual").get<double>();
    r.seconds = j.at("seconds").get<double>();
    r.iterations = j.at("iterations").get<int>();
    const std::string status = j.at("status").get<std::string>();
    const std::optional<PerturbationStatus> known = PerturbationStatusFromString(status);
    if (!known)
      throw InputError(where, 0, "bad perturbation record: unknown status '" + status + "'");
    r.status = *known;
    r.message = j.at("message").get<std::string>();
    r.backend = j.at("backend").get<std::string>();
    r.rattler = j.at("rattler").get<bool>();
    r.displacement_profile = FromNulls(j.at("displacement_profile"));
    r.force_profile = FromNulls(j.at("force_profile"));
    r.field = j.at("field").get<std::vector<double>>();
    r.field_count = j.at("field_count").get<std::vector<int>>();
    r.stress = j.at("stress").get<std::vector<double>>();
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where, 0, std::string("bad perturbation record: ") + e.what());
  }
}

std::map<int, ReducedResponse> RecordsByIndex(const std::vector<RunRecords::Entry>& entries) {
  std::map<int, ReducedResponse> out;
  for (const RunRecords::Entry& e : entries) {
    if (!e.record.contains("index") || !e.record["index"].is_number_integer())
      throw InputError(e.file.string(), e.line, "record without an integer \"index\"");
    out.emplace(e.record["index"].get<int>(), ReducedResponseFromJson(e.record, e.Where()));
  }
  return out;
}

}  // namespace unjam
