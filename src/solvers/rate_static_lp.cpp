#include <cstdio>
#include <limits>

#include "../problem/lp_triplets.hpp"
#include "unjam/solvers/rate_path.hpp"

namespace unjam {

RateStaticLp SolveRateStaticLp(const RateProblem& p) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const int dims = static_cast<int>(p.basis.cols());
  lp::LpTriplets lp;
  lp.AddColumns(dims, -kInfinity, kInfinity, 0.0);
  auto add_row = [&](const Eigen::VectorXd& row, double lower, double upper) {
    const int r = lp.AddRow(lower, upper);
    for (int d = 0; d < dims; ++d) {
      if (row[d] != 0.0) lp.Add(r, d, row[d]);
    }
  };
  for (const RateContact& c : p.contacts) {
    if (c.held) continue;
    const Eigen::VectorXd n = p.basis.row(c.row_n).transpose();
    if (c.row_t < 0) {
      add_row(n, -c.r0_n, kInfinity);  // r_n ≥ 0
      continue;
    }
    const Eigen::VectorXd t = p.basis.row(c.row_t).transpose();
    add_row(c.mu * n - t, -(c.mu * c.r0_n - c.r0_t), kInfinity);  // μ r_n − r_t ≥ 0
    add_row(c.mu * n + t, -(c.mu * c.r0_n + c.r0_t), kInfinity);  // μ r_n + r_t ≥ 0
  }
  for (int row : p.released_rows) {
    double r0 = 0.0;
    for (const RateContact& c : p.contacts) {
      if (c.row_n == row) r0 = c.r0_n;
      if (c.row_t == row) r0 = c.r0_t;
    }
    add_row(p.basis.row(row).transpose(), -r0, -r0);
  }
  ClpSimplex model;
  // Forces are O(1) (impulses of the static network): CLP's tolerances relative to them.
  lp::LoadIntoClp(lp, 1e-9, model);
  model.initialSolve();
  RateStaticLp out;
  out.iterations = model.numberIterations();
  out.decided = model.isProvenOptimal() || model.isProvenPrimalInfeasible();
  out.feasible = model.isProvenOptimal();
  char text[160];
  std::snprintf(text, sizeof text, "static LP (%d variables, %d rows, %d iterations): %s", dims, lp.NumRows(),
                out.iterations, out.feasible ? "feasible" : out.decided ? "infeasible" : "undecided");
  out.message = text;
  return out;
}

}  // namespace unjam
