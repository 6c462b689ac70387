// What became of one perturbation: the one status every record, table and summary shows
// (docs/perturbations.md). Its text is what records and CSV files hold.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace unjam {

enum class PerturbationStatus {
  kOk,            // resolved, quasi-static and linear in ξ: a result to use
  kNotConverged,  // the step's residual missed the tolerance: no answer
  kDynamic,       // resolved but not quasi-static, or no static network holds it
  kNonlinear,     // quasi-static, but not the same response at 10ξ
  kBlocked,       // no motion satisfies the step's non-penetration
};

const char* ToString(PerturbationStatus status);
std::ostream& operator<<(std::ostream& os, PerturbationStatus status);  // its text

// The status a record names; none for any other text.
std::optional<PerturbationStatus> PerturbationStatusFromString(const std::string& text);

}  // namespace unjam
