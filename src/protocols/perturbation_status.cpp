#include "unjam/protocols/perturbation_status.hpp"

#include <array>
#include <ostream>
#include <utility>

namespace unjam {

namespace {
constexpr std::array<std::pair<PerturbationStatus, const char*>, 5> kNames{{
    {PerturbationStatus::kOk, "ok"},
    {PerturbationStatus::kNotConverged, "not-converged"},
    {PerturbationStatus::kDynamic, "dynamic"},
    {PerturbationStatus::kNonlinear, "nonlinear"},
    {PerturbationStatus::kBlocked, "blocked"},
}};
}  // namespace

const char* ToString(PerturbationStatus status) {
  for (const auto& [value, name] : kNames) {
    if (value == status) return name;
  }
  return "?";
}

std::ostream& operator<<(std::ostream& os, PerturbationStatus status) {
  return os << ToString(status);
}

std::optional<PerturbationStatus> PerturbationStatusFromString(const std::string& text) {
  for (const auto& [value, name] : kNames) {
    if (text == name) return value;
  }
  return std::nullopt;
}

}  // namespace unjam
