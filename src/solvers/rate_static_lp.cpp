#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include "unjam/lp/lp_triplets.hpp"
#include "unjam/solvers/rate_path.hpp"

namespace unjam {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Forces are O(1) (impulses of the static network): CLP's tolerances relative to them.
constexpr double kTolerance = 1e-9;

// The LP's rows: A α ≥ b (every contact but the held one in its Coulomb cone) and E α = e
// (the released forces at zero).
struct StaticRows {
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  Eigen::MatrixXd e;
  Eigen::VectorXd e_value;
};

StaticRows RowsOf(const RateProblem& p) {
  std::vector<Eigen::VectorXd> rows;
  std::vector<double> lower;
  for (const RateContact& c : p.contacts) {
    if (c.held) continue;
    const Eigen::VectorXd n = p.basis.row(c.row_n).transpose();
    if (c.row_t < 0) {
      rows.push_back(n);  // r_n ≥ 0
      lower.push_back(-c.r0_n);
      continue;
    }
    const Eigen::VectorXd t = p.basis.row(c.row_t).transpose();
    rows.push_back(c.mu * n - t);  // μ r_n − r_t ≥ 0
    lower.push_back(-(c.mu * c.r0_n - c.r0_t));
    rows.push_back(c.mu * n + t);  // μ r_n + r_t ≥ 0
    lower.push_back(-(c.mu * c.r0_n + c.r0_t));
  }
  StaticRows out;
  out.a.resize(static_cast<Eigen::Index>(rows.size()), p.basis.cols());
  out.b.resize(out.a.rows());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    out.a.row(static_cast<Eigen::Index>(k)) = rows[k].transpose();
    out.b[static_cast<Eigen::Index>(k)] = lower[k];
  }
  out.e.resize(static_cast<Eigen::Index>(p.released_rows.size()), p.basis.cols());
  out.e_value.resize(out.e.rows());
  for (std::size_t k = 0; k < p.released_rows.size(); ++k) {
    out.e.row(static_cast<Eigen::Index>(k)) = p.basis.row(p.released_rows[k]);
    out.e_value[static_cast<Eigen::Index>(k)] = -p.StaticImpulse(p.released_rows[k]);
  }
  return out;
}

// A Farkas certificate of infeasibility of the rows L ≤ A α ≤ U (α free): multipliers y with
// Aᵀy = 0 and Σ_i (y_i > 0 ? y_i L_i : y_i U_i) > 0, checked in double precision on CLP's
// ray (either sign). No α can meet the rows: yᵀAα = 0 but yᵀAα ≥ that sum.
bool FarkasCertifies(const lp::LpTriplets& lp, const ClpSimplex& model) {
  double* raw = model.infeasibilityRay();
  if (raw == nullptr) return false;
  const Eigen::VectorXd ray = Eigen::Map<const Eigen::VectorXd>(raw, lp.NumRows());
  delete[] raw;
  for (const double sign : {1.0, -1.0}) {
    const Eigen::VectorXd y = sign * ray;
    Eigen::VectorXd aty = Eigen::VectorXd::Zero(lp.NumColumns());
    double scale = 0.0;
    for (std::size_t k = 0; k < lp.values.size(); ++k) {
      aty[lp.cols[k]] += y[lp.rows[k]] * lp.values[k];
      scale += std::abs(y[lp.rows[k]] * lp.values[k]);
    }
    double bound = 0.0, size = 0.0;
    const double largest = y.cwiseAbs().maxCoeff();
    bool finite = true;
    for (Eigen::Index i = 0; i < y.size(); ++i) {
      const double limit = y[i] > 0.0 ? lp.row_lower[static_cast<std::size_t>(i)]
                                      : lp.row_upper[static_cast<std::size_t>(i)];
      if (y[i] == 0.0) continue;
      if (!std::isfinite(limit)) {
        finite = finite && std::abs(y[i]) <= 1e-12 * largest;
        continue;
      }
      bound += y[i] * limit;
      size += std::abs(y[i]) * (1.0 + std::abs(limit));
    }
    // Forces are O(1): the certificate must clear round-off by a wide margin.
    if (finite && size > 0.0 && aty.cwiseAbs().maxCoeff() <= 1e-10 * std::max(scale, 1e-300) &&
        bound > 1e-7 * size)
      return true;
  }
  return false;
}

struct Verdict {
  RateStaticLp lp;
  Eigen::VectorXd alpha;  // a feasible point, where there is one
};

// The feasibility LP over the inequality rows `subset` and every equality row (CLP).
Verdict SolveOver(const StaticRows& s, const std::vector<int>& subset) {
  const int dims = static_cast<int>(s.a.cols());
  lp::LpTriplets lp;
  lp.AddColumns(dims, -kInfinity, kInfinity, 0.0);
  auto add_row = [&](const Eigen::VectorXd& row, double lower, double upper) {
    const int r = lp.AddRow(lower, upper);
    for (int d = 0; d < dims; ++d) {
      if (row[d] != 0.0) lp.Add(r, d, row[d]);
    }
  };
  for (int r : subset) add_row(s.a.row(r).transpose(), s.b[r], kInfinity);
  for (Eigen::Index r = 0; r < s.e.rows(); ++r)
    add_row(s.e.row(r).transpose(), s.e_value[r], s.e_value[r]);
  ClpSimplex model;
  lp::LoadIntoClp(lp, kTolerance, model);
  // The dual simplex first: CLP's initialSolve spends tens of seconds proving some of
  // these LPs infeasible (measured at N = 3000), the dual simplex 1–3 s. But the dual
  // simplex also calls some feasible ones infeasible (12 of 643 openings at N = 500): its
  // infeasibility counts only with a Farkas certificate checked here, else initialSolve
  // decides.
  model.dual();
  int iterations = model.numberIterations();
  bool infeasible = model.isProvenPrimalInfeasible() && FarkasCertifies(lp, model);
  if (!model.isProvenOptimal() && !infeasible) {
    model.initialSolve();
    iterations += model.numberIterations();
    infeasible = model.isProvenPrimalInfeasible();
  }
  Verdict v;
  v.lp.iterations = iterations;
  v.lp.decided = model.isProvenOptimal() || infeasible;
  v.lp.feasible = model.isProvenOptimal();
  if (v.lp.feasible)
    v.alpha = Eigen::Map<const Eigen::VectorXd>(model.primalColumnSolution(), dims);
  return v;
}

// The rows nearest to binding at α = 0, the static forces (which meet them all): the rows
// an infeasibility is made of are among them, in every case measured.
std::vector<int> NearestRows(const StaticRows& s, std::size_t count) {
  std::vector<int> order(static_cast<std::size_t>(s.a.rows()));
  std::iota(order.begin(), order.end(), 0);
  count = std::min(count, order.size());
  const Eigen::VectorXd slack = -s.b.array() / s.a.rowwise().norm().array().max(1e-300);
  std::partial_sort(
      order.begin(), order.begin() + static_cast<std::ptrdiff_t>(count), order.end(),
      [&](int x, int y) { return slack[x] < slack[y] || (slack[x] == slack[y] && x < y); });
  order.resize(count);
  return order;
}

}  // namespace

RateStaticLp SolveRateStaticLp(const RateProblem& p, const RateStaticLpOptions& options) {
  const StaticRows rows = RowsOf(p);
  const int dims = static_cast<int>(rows.a.cols());
  const int total = static_cast<int>(rows.a.rows() + rows.e.rows());
  // Cutting planes: the LP over a subset of the rows is a relaxation. Where it has no
  // feasible point the whole LP has none; where its point meets every row the whole LP has
  // one. Otherwise the rows its point violates most join the subset, up to kRounds times;
  // then the LP over every row decides.
  constexpr int kRounds = 8;
  std::vector<int> subset;
  if (!options.every_row) subset = NearestRows(rows, static_cast<std::size_t>(4 * dims));
  std::vector<char> in_subset(static_cast<std::size_t>(rows.a.rows()), 0);
  for (int r : subset) in_subset[static_cast<std::size_t>(r)] = 1;
  Verdict v;
  int iterations = 0;
  bool proven = false;
  for (int round = 0; round < kRounds && !subset.empty(); ++round) {
    v = SolveOver(rows, subset);
    iterations += v.lp.iterations;
    if (!v.lp.decided) break;
    if (!v.lp.feasible) {
      proven = true;
      break;
    }
    const Eigen::VectorXd violation = rows.a * v.alpha - rows.b;
    std::vector<int> violated;
    for (Eigen::Index r = 0; r < violation.size(); ++r) {
      if (violation[r] < -kTolerance && in_subset[static_cast<std::size_t>(r)] == 0)
        violated.push_back(static_cast<int>(r));
    }
    proven = violation.minCoeff() >= -kTolerance;
    // Done, or only rows of the subset itself are off (by CLP's scaled tolerance): the
    // same LP again would change nothing, the LP over every row decides.
    if (proven || violated.empty()) break;
    const std::size_t take = std::min(violated.size(), static_cast<std::size_t>(4 * dims));
    std::partial_sort(violated.begin(), violated.begin() + static_cast<std::ptrdiff_t>(take),
                      violated.end(), [&](int x, int y) { return violation[x] < violation[y]; });
    for (std::size_t k = 0; k < take; ++k) {
      subset.push_back(violated[k]);
      in_subset[static_cast<std::size_t>(violated[k])] = 1;
    }
  }
  const char* method = "cutting planes";
  int used = static_cast<int>(subset.size() + rows.e.rows());
  if (!proven) {
    std::vector<int> every(static_cast<std::size_t>(rows.a.rows()));
    std::iota(every.begin(), every.end(), 0);
    v = SolveOver(rows, every);
    iterations += v.lp.iterations;
    method = "every row";
    used = total;
  }
  v.lp.iterations = iterations;
  RateStaticLp out = v.lp;
  char text[200];
  std::snprintf(text, sizeof text, "static LP (%d variables, %d rows; %s: %d, %d iterations): %s",
                dims, total, method, used, out.iterations,
                out.feasible  ? "feasible"
                : out.decided ? "infeasible"
                              : "undecided");
  out.message = text;
  return out;
}

}  // namespace unjam
