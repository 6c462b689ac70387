#include "nearest_lp.hpp"

#include <limits>
#include <vector>

#include <ClpSimplex.hpp>
#include <CoinPackedMatrix.hpp>

namespace unjam::indeterminacy_internal {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Columns [f | d⁺ | d⁻] (n each); rows [A f = b | cone rows | f − d⁺ + d⁻ = f⁰].
struct Lp {
  std::vector<int> rows, cols;
  std::vector<double> values;
  std::vector<double> col_lower, col_upper, objective, row_lower, row_upper;

  void Add(int row, int col, double value) {
    rows.push_back(row);
    cols.push_back(col);
    values.push_back(value);
  }
  int AddRow(double lower, double upper) {
    row_lower.push_back(lower);
    row_upper.push_back(upper);
    return static_cast<int>(row_lower.size()) - 1;
  }
};

Lp BuildLp(const EquilibriumSystem& s, const Eigen::VectorXd& reference) {
  const int n = s.NumUnknowns();
  const int stride = s.UnknownsPerContact();
  const double scale = 1.0 / s.force_scale;
  Lp lp;
  lp.col_lower.assign(3 * n, 0.0);
  lp.col_upper.assign(3 * n, kInfinity);
  lp.objective.assign(3 * n, 1.0);
  for (int c = 0; c < n; ++c) {
    lp.objective[c] = 0.0;
    if (c % stride == 1) lp.col_lower[c] = -kInfinity;  // f_t is free; the cone bounds it
  }
  for (int r = 0; r < s.NumRows(); ++r) lp.AddRow(scale * s.load[r], scale * s.load[r]);
  for (int k = 0; k < s.matrix.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(s.matrix, k); it; ++it) {
      lp.Add(static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
    }
  }
  if (s.frictional) {
    for (int k = 0; k < n / 2; ++k) {
      for (double sign : {1.0, -1.0}) {  // ±f_t − μ f_n ≤ 0
        const int row = lp.AddRow(-kInfinity, 0.0);
        lp.Add(row, 2 * k + 1, sign);
        lp.Add(row, 2 * k, -s.mu);
      }
    }
  }
  for (int c = 0; c < n; ++c) {
    const int row = lp.AddRow(scale * reference[c], scale * reference[c]);
    lp.Add(row, c, 1.0);
    lp.Add(row, n + c, -1.0);
    lp.Add(row, 2 * n + c, 1.0);
  }
  return lp;
}

}  // namespace

LpOutcome NearestAdmissibleByLinearProgram(const EquilibriumSystem& s, const Eigen::VectorXd& reference) {
  const Lp lp = BuildLp(s, reference);
  const CoinPackedMatrix matrix(true, lp.rows.data(), lp.cols.data(), lp.values.data(),
                                static_cast<CoinBigIndex>(lp.values.size()));
  ClpSimplex model;
  model.setLogLevel(0);
  model.loadProblem(matrix, lp.col_lower.data(), lp.col_upper.data(), lp.objective.data(),
                    lp.row_lower.data(), lp.row_upper.data());
  model.setPrimalTolerance(1e-10);
  model.setDualTolerance(1e-10);
  model.dual();
  LpOutcome out;
  if (model.isProvenPrimalInfeasible()) {
    out.status = AdmissibleStatus::kInfeasible;
    out.message = "no admissible force network: the packing is not static";
    return out;
  }
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
