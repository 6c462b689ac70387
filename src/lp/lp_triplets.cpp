#include "unjam/lp/lp_triplets.hpp"

#include <limits>

#include <CoinPackedMatrix.hpp>

namespace unjam::lp {

int LpTriplets::AddColumns(int n, double lower, double upper, double cost) {
  const int first = NumColumns();
  col_lower.resize(first + n, lower);
  col_upper.resize(first + n, upper);
  objective.resize(first + n, cost);
  return first;
}

int LpTriplets::AddRow(double lower, double upper) {
  row_lower.push_back(lower);
  row_upper.push_back(upper);
  return NumRows() - 1;
}

void AddL1Distance(LpTriplets& lp, int first, const Eigen::VectorXd& target) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const int n = static_cast<int>(target.size());
  const int plus = lp.AddColumns(n, 0.0, kInfinity, 1.0);
  const int minus = lp.AddColumns(n, 0.0, kInfinity, 1.0);
  for (int c = 0; c < n; ++c) {
    const int row = lp.AddRow(target[c], target[c]);
    lp.Add(row, first + c, 1.0);
    lp.Add(row, plus + c, -1.0);
    lp.Add(row, minus + c, 1.0);
  }
}

void LoadIntoClp(const LpTriplets& lp, ClpSimplex& model) {
  CoinPackedMatrix matrix(true, lp.rows.data(), lp.cols.data(), lp.values.data(),
                          static_cast<CoinBigIndex>(lp.values.size()));
  matrix.setDimensions(lp.NumRows(), lp.NumColumns());
  model.setLogLevel(0);
  model.loadProblem(matrix, lp.col_lower.data(), lp.col_upper.data(), lp.objective.data(),
                    lp.row_lower.data(), lp.row_upper.data());
}

void LoadIntoClp(const LpTriplets& lp, double tolerance, ClpSimplex& model) {
  LoadIntoClp(lp, model);
  model.setPrimalTolerance(tolerance);
  model.setDualTolerance(tolerance);
}

}  // namespace unjam::lp
