#include "ensemble_lp.hpp"

#include <limits>

namespace unjam::indeterminacy_internal {

LpTriplets EnsembleLp(const EquilibriumSystem& s) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const int n = s.NumUnknowns();
  LpTriplets lp;
  lp.AddColumns(n, 0.0, kInfinity);
  for (int r = 0; r < s.NumRows(); ++r)
    lp.AddRow(s.load[r] / s.force_scale, s.load[r] / s.force_scale);
  for (int k = 0; k < s.matrix.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(s.matrix, k); it; ++it) {
      lp.Add(static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
    }
  }
  if (!s.frictional) return lp;
  for (int k = 0; k < n / 2; ++k) {
    lp.col_lower[2 * k + 1] = -kInfinity;  // f_t is free; the cone bounds it
    for (double sign : {1.0, -1.0}) {
      const int row = lp.AddRow(-kInfinity, 0.0);
      lp.Add(row, 2 * k + 1, sign);
      lp.Add(row, 2 * k, -s.mu);
    }
  }
  return lp;
}

std::unique_ptr<ClpSimplex> EnsembleModel(const EquilibriumSystem& s, double tolerance) {
  auto model = std::make_unique<ClpSimplex>();
  lp::LoadIntoClp(EnsembleLp(s), tolerance, *model);
  return model;
}

Bound Outcome(ClpSimplex& model, double sign, double scale) {
  Bound b;
  if (model.isProvenOptimal()) {
    b.status = BoundStatus::kOptimal;
    b.value = sign * model.objectiveValue() * scale;
  } else if (model.isProvenDualInfeasible()) {
    b.status = BoundStatus::kUnbounded;
  } else if (model.isProvenPrimalInfeasible()) {
    b.status = BoundStatus::kInfeasible;
  }
  return b;
}

void Simplex(ClpSimplex& model, bool dual_first, int keep, bool confirm, long long& iterations) {
  if (dual_first) model.dual(0, keep);
  else model.primal(0, keep);
  iterations += model.numberIterations();
  if (model.isProvenOptimal() || !confirm) return;
  model.allSlackBasis(true);
  if (dual_first) model.primal();
  else model.dual();
  iterations += model.numberIterations();
}

}  // namespace unjam::indeterminacy_internal
