#include "nearest_lp.hpp"

#include <string>

#include "ensemble_lp.hpp"

namespace unjam::indeterminacy_internal {

namespace {

// Whether any admissible network exists: the ensemble alone, no objective. On the
// certificates of an N = 4000 cell it took 16-19 s where the nearest-network LP took 45 s
// to find none, and most certificates of a creeping packing find none.
bool ProvenInfeasible(const LpTriplets& ensemble) {
  ClpSimplex model;
  lp::LoadIntoClp(ensemble, 1e-10, model);
  model.dual();
  return model.isProvenPrimalInfeasible();
}

LpOutcome Infeasible() {
  LpOutcome out;
  out.status = AdmissibleStatus::kInfeasible;
  out.message = "no admissible force network: the packing is not static";
  return out;
}

}  // namespace

LpOutcome NearestAdmissibleByLinearProgram(const EquilibriumSystem& s,
                                           const Eigen::VectorXd& reference) {
  LpTriplets lp = EnsembleLp(s);
  if (ProvenInfeasible(lp)) return Infeasible();
  // Columns [f | d⁺ | d⁻]; rows [the ensemble | f − d⁺ + d⁻ = f⁰ / F].
  lp::AddL1Distance(lp, 0, reference / s.force_scale);
  ClpSimplex model;
  lp::LoadIntoClp(lp, 1e-10, model);
  model.dual();
  LpOutcome out;
  if (model.isProvenPrimalInfeasible()) return Infeasible();
  if (!model.isProvenOptimal()) {
    out.message = "CLP stopped with status " + std::to_string(model.status());
    return out;
  }
  const double* x = model.getColSolution();
  out.forces = Eigen::Map<const Eigen::VectorXd>(x, s.NumUnknowns()) * s.force_scale;
  out.status = AdmissibleStatus::kAdmissible;
  return out;
}

}  // namespace unjam::indeterminacy_internal
