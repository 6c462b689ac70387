// Stage 2 of the admissible-force certificate (admissible_forces.hpp): the admissible forces
// nearest to a reference in the L1 norm, a linear program solved by COIN-OR CLP.
// Internal to src/indeterminacy.
#pragma once

#include <string>

#include <Eigen/Core>

#include "unjam/indeterminacy/admissible_forces.hpp"

namespace unjam::indeterminacy_internal {

struct LpOutcome {
  AdmissibleStatus status = AdmissibleStatus::kFailed;
  Eigen::VectorXd forces;  // when admissible
  std::string message;
};

//   minimise Σ |f − f⁰| / F   subject to  A f = b,  f_n ≥ 0,  |f_t| ≤ μ f_n
// (F the force scale; the problem is scaled by it so that CLP's tolerances are relative).
LpOutcome NearestAdmissibleByLinearProgram(const EquilibriumSystem& system,
                                           const Eigen::VectorXd& reference);

}  // namespace unjam::indeterminacy_internal
