#include "nearest_lp.hpp"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "ensemble_lp.hpp"

namespace unjam::indeterminacy_internal {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Columns [f | d⁺ | d⁻] (n each); rows [the ensemble (ensemble_lp.hpp) | f − d⁺ + d⁻ = f⁰].
struct Lp {
  LpTriplets model;
  std::vector<double> objective;
};

Lp BuildLp(const EquilibriumSystem& s, LpTriplets ensemble, const Eigen::VectorXd& reference) {
  const int n = s.NumUnknowns();
  Lp lp{std::move(ensemble), std::vector<double>(3 * n, 1.0)};
  std::fill(lp.objective.begin(), lp.objective.begin() + n, 0.0);
  lp.model.col_lower.resize(3 * n, 0.0);
  lp.model.col_upper.resize(3 * n, kInfinity);
  for (int c = 0; c < n; ++c) {
    const int row = lp.model.AddRow(reference[c] / s.force_scale, reference[c] / s.force_scale);
    lp.model.Add(row, c, 1.0);
    lp.model.Add(row, n + c, -1.0);
    lp.model.Add(row, 2 * n + c, 1.0);
  }
  return lp;
}

// Whether any admissible network exists: the ensemble alone, no objective. On the
// certificates of an N = 4000 cell it took 16-19 s where the nearest-network LP took 45 s
// to find none, and most certificates of a creeping packing find none.
bool ProvenInfeasible(const LpTriplets& ensemble) {
  ClpSimplex model;
  LoadIntoClp(ensemble, std::vector<double>(ensemble.col_lower.size(), 0.0), 1e-10, model);
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

LpOutcome NearestAdmissibleByLinearProgram(const EquilibriumSystem& s, const Eigen::VectorXd& reference) {
  LpTriplets ensemble = EnsembleLp(s);
  if (ProvenInfeasible(ensemble)) return Infeasible();
  const Lp lp = BuildLp(s, std::move(ensemble), reference);
  ClpSimplex model;
  LoadIntoClp(lp.model, lp.objective, 1e-10, model);
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
