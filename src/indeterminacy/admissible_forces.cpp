#include "unjam/indeterminacy/admissible_forces.hpp"

#include <chrono>
#include <optional>

#include "nearest_lp.hpp"
#include "region_projection.hpp"

namespace unjam {

using indeterminacy_internal::ClassifyRegions;
using indeterminacy_internal::ProjectOntoAdmissible;

const char* ToString(AdmissibleStatus status) {
  switch (status) {
    case AdmissibleStatus::kAdmissible: return "admissible";
    case AdmissibleStatus::kInfeasible: return "infeasible";
    case AdmissibleStatus::kFailed: return "failed";
  }
  return "unknown";
}

double BalanceResidual(const EquilibriumSystem& s, const Eigen::VectorXd& forces) {
  if (s.NumRows() == 0) return 0.0;
  return (s.matrix * forces - s.load).lpNorm<Eigen::Infinity>() / s.force_scale;
}

AdmissibleForces NearestAdmissibleForces(const EquilibriumSystem& s,
                                         const Eigen::VectorXd& reference,
                                         const AdmissibleOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  AdmissibleForces out;
  std::optional<Eigen::VectorXd> projected;
  if (o.method != AdmissibleMethod::kLinearProgram) {
    projected = ProjectOntoAdmissible(s, reference, ClassifyRegions(s, reference, o.edge_tolerance),
                                      o.balance_tolerance);
  }
  if (projected) {
    out.status = AdmissibleStatus::kAdmissible;
    out.forces = std::move(*projected);
    out.method = "projection";
  } else if (o.method != AdmissibleMethod::kProjection) {
    indeterminacy_internal::LpOutcome lp =
        indeterminacy_internal::NearestAdmissibleByLinearProgram(s, reference);
    out.status = lp.status;
    out.message = lp.message;
    if (lp.status == AdmissibleStatus::kAdmissible) {
      // The simplex solution is feasible to CLP's tolerance; balance it to round-off.
      auto polished = ProjectOntoAdmissible(
          s, lp.forces, ClassifyRegions(s, lp.forces, o.edge_tolerance), o.balance_tolerance);
      out.method = "linear-program";
      if (polished) {
        out.forces = std::move(*polished);
      } else {
        out.status = AdmissibleStatus::kFailed;
        out.message = "the linear program's forces could not be balanced to the tolerance";
        out.forces = std::move(lp.forces);
      }
    }
  } else {
    out.message = "the projection found no admissible forces near the reference";
  }
  if (out.forces.size() > 0) out.balance_residual = BalanceResidual(s, out.forces);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace unjam
