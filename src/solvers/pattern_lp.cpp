#include "unjam/solvers/pattern_lp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <ClpSimplex.hpp>
#include <CoinPackedMatrix.hpp>
#include <Eigen/SparseCore>

namespace unjam {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

enum class State { kOpen, kSticking, kSlidingForward, kSlidingBackward, kHeld };

// Per contact, the state of the candidate answer, by the natural map of its law with the
// impulses in units of R and the posed velocities ũ in units of V / κ: z = r / R − κ ũ / V;
// open if z_n < 0, sliding forward (backward) if z_t < −μ z_n (> μ z_n), else sticking.
// For an exact answer every κ > 0 gives its own pattern (ties at zero count as closed and
// sticking); for an inexact one a small κ trusts its forces, a large one its velocities.
std::vector<State> PatternOf(const ContactProblem& p, const Eigen::VectorXd& candidate, double r_scale,
                             double v_scale, double weight, PatternCounts& counts) {
  const Eigen::VectorXd posed = PosedContactVelocity(p, candidate);
  const int per = p.UnknownsPerContact();
  std::vector<State> states(p.NumContacts());
  for (int k = 0; k < p.NumContacts(); ++k) {
    State& s = states[k];
    const double z_n = candidate[per * k] / r_scale - weight * posed[per * k] / v_scale;
    const double z_t = per == 2 ? candidate[per * k + 1] / r_scale - weight * posed[per * k + 1] / v_scale : 0.0;
    const double limit = p.contacts[k].mu * z_n;
    if (p.contacts[k].kind == ConstraintKind::kBilateral) {
      s = State::kHeld;
      ++counts.held;
    } else if (z_n < 0.0) {
      s = State::kOpen;
      ++counts.open;
    } else if (per == 2 && std::abs(z_t) > limit) {
      s = z_t < 0.0 ? State::kSlidingForward : State::kSlidingBackward;
      ++counts.sliding;
    } else {
      s = State::kSticking;
      ++counts.sticking;
    }
  }
  return states;
}

// Rows, columns and bounds of a CLP model, built up in triplets.
struct Lp {
  std::vector<int> rows, cols;
  std::vector<double> values, col_lower, col_upper, row_lower, row_upper, objective;

  int AddColumns(int n, double lower, double upper, double cost) {
    const int first = static_cast<int>(col_lower.size());
    col_lower.resize(first + n, lower);
    col_upper.resize(first + n, upper);
    objective.resize(first + n, cost);
    return first;
  }
  int AddRow(double lower, double upper) {
    row_lower.push_back(lower);
    row_upper.push_back(upper);
    return static_cast<int>(row_lower.size()) - 1;
  }
  void Add(int row, int col, double value) {
    rows.push_back(row);
    cols.push_back(col);
    values.push_back(value);
  }
};

// Adds columns e⁺, e⁻ ≥ 0 and rows x_c − e⁺ + e⁻ = target_c for the columns [first,
// first + n): the LP then minimises Σ |x − target| (its only costs).
void AddL1Distance(Lp& lp, int first, int n, const Eigen::VectorXd& target) {
  const int plus = lp.AddColumns(n, 0.0, kInfinity, 1.0);
  const int minus = lp.AddColumns(n, 0.0, kInfinity, 1.0);
  for (int c = 0; c < n; ++c) {
    const int row = lp.AddRow(target[c], target[c]);
    lp.Add(row, first + c, 1.0);
    lp.Add(row, plus + c, -1.0);
    lp.Add(row, minus + c, 1.0);
  }
}

// Stage 1, the quasi-static limit: the impulses r̂ = r / R nearest the reference that the
// pattern's laws allow and that balance the step's load with no motion, Hᵀ r = −M v_free
// (the response is O(ξ) and its inertia O(ξ) of the forces). Columns r̂, e⁺, e⁻; rows: the
// balance, the pattern's friction, r̂ − e⁺ + e⁻ = reference / R.
Lp BuildStaticLp(const ContactProblem& p, const std::vector<State>& states, const Eigen::VectorXd& reference,
                 double r_scale) {
  const int dofs = p.NumDofs(), unknowns = p.NumUnknowns(), per = p.UnknownsPerContact();
  const Eigen::SparseMatrix<double, Eigen::RowMajor> h = AssembleJacobian(p);
  const Eigen::VectorXd inv_mass = InverseMassDiagonal(p);
  const Eigen::VectorXd v_free = FreeVelocityVector(p);
  Lp lp;
  const int r = lp.AddColumns(unknowns, -kInfinity, kInfinity, 0.0);
  for (int d = 0; d < dofs; ++d) {
    const double load = -v_free[d] / inv_mass[d] / r_scale;
    lp.AddRow(load, load);
  }
  for (int u = 0; u < unknowns; ++u) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(h, u); it; ++it) {
      lp.Add(static_cast<int>(it.col()), r + u, it.value());
    }
  }
  auto fix = [&](int u) { lp.col_lower[r + u] = lp.col_upper[r + u] = 0.0; };
  auto friction_row = [&](int k, double sign, double lower, double upper) {  // r_t + sign μ r_n
    const int row = lp.AddRow(lower, upper);
    lp.Add(row, r + per * k + 1, 1.0);
    lp.Add(row, r + per * k, sign * p.contacts[k].mu);
  };
  for (int k = 0; k < p.NumContacts(); ++k) {
    const int n = per * k;
    if (states[k] != State::kHeld) lp.col_lower[r + n] = 0.0;
    if (states[k] == State::kOpen) fix(n);
    if (per == 1) continue;
    switch (states[k]) {
      case State::kOpen:
      case State::kHeld: fix(n + 1); break;
      case State::kSticking:
        friction_row(k, -1.0, -kInfinity, 0.0);
        friction_row(k, 1.0, 0.0, kInfinity);
        break;
      case State::kSlidingForward: friction_row(k, 1.0, 0.0, 0.0); break;    // ũ_t > 0: r_t = −μ r_n
      case State::kSlidingBackward: friction_row(k, -1.0, 0.0, 0.0); break;  // ũ_t < 0: r_t = +μ r_n
    }
  }
  AddL1Distance(lp, r, unknowns, reference / r_scale);
  return lp;
}

// Stage 2, the motion, on the scale of the response: the impulse change Δr = S ŝ nearest
// zero (L1) that gives stage 1's forces r⁰ the pattern's velocities. S = V / w̄ (w̄ the
// mean diagonal of W = H M⁻¹ Hᵀ) makes ŝ of order one. Columns ŵ = Δv / V and ŝ; rows,
// with ũ⁰ = H v(r⁰) + offset the velocities of the forces of stage 1:
//   the velocity change:       ŵ − (M⁻¹ / w̄) Hᵀ ŝ = 0
//   the pattern's velocities:  ũ⁰_u / V + (H ŵ)_u  =, ≥ or ≤  0
//   its laws on r⁰ + S ŝ:      sliding Δr_t = ∓μ Δr_n, open Δr = 0, held Δr_t = 0,
//                              r_n ≥ 0 and the cone of sticking contacts (slack / S).
// (Over W itself, ŝ alone, the same LP took 10× longer: W's rows are twice as full and its
// bases worse conditioned.)
// Bounds whose slack is above kFarBound response sizes are left out: no O(1) ŝ reaches them.
constexpr double kFarBound = 1e6;

Lp BuildMotionLp(const ContactProblem& p, const std::vector<State>& states, const Eigen::VectorXd& forces,
                 double v_scale, double& s_scale) {
  const int unknowns = p.NumUnknowns(), per = p.UnknownsPerContact(), dofs = p.NumDofs();
  const Eigen::SparseMatrix<double, Eigen::RowMajor> h = AssembleJacobian(p);
  const Eigen::VectorXd inv_mass = InverseMassDiagonal(p);
  // w̄: the mean of diag W = H M⁻¹ Hᵀ.
  double w_mean = 0.0;
  for (int u = 0; u < unknowns; ++u) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(h, u); it; ++it) {
      w_mean += it.value() * it.value() * inv_mass[it.col()];
    }
  }
  w_mean = std::max(w_mean / std::max(unknowns, 1), 1e-300);
  s_scale = v_scale / w_mean;
  const Eigen::VectorXd posed = PosedContactVelocity(p, forces);
  Lp lp;
  // Columns ŵ = Δv / V and ŝ; rows ŵ − (M⁻¹ / w̄) Hᵀ ŝ = 0 (the velocity change Δr makes).
  const int v = lp.AddColumns(dofs, -kInfinity, kInfinity, 0.0);
  const int s = lp.AddColumns(unknowns, -kInfinity, kInfinity, 0.0);
  for (int d = 0; d < dofs; ++d) lp.Add(lp.AddRow(0.0, 0.0), v + d, 1.0);
  for (int u = 0; u < unknowns; ++u) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(h, u); it; ++it) {
      lp.Add(static_cast<int>(it.col()), s + u, -it.value() * inv_mass[it.col()] / w_mean);
    }
  }
  auto velocity_row = [&](int u, double lower, double upper) {  // ũ⁰/V + H ŵ within bounds
    const double at = posed[u] / v_scale;
    const int row = lp.AddRow(lower - at, upper - at);
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(h, u); it; ++it) {
      lp.Add(row, v + static_cast<int>(it.col()), it.value());
    }
  };
  auto bounded = [&](double slack) { return slack / s_scale < kFarBound; };
  auto fix = [&](int u) { lp.col_lower[s + u] = lp.col_upper[s + u] = 0.0; };
  auto friction_row = [&](int k, double sign, double lower, double upper) {  // Δr_t + sign μ Δr_n
    const int row = lp.AddRow(lower, upper);
    lp.Add(row, s + per * k + 1, 1.0);
    lp.Add(row, s + per * k, sign * p.contacts[k].mu);
  };
  for (int k = 0; k < p.NumContacts(); ++k) {
    const int n = per * k, t = n + 1;
    const double r_n = forces[n];
    if (states[k] != State::kHeld && states[k] != State::kOpen && bounded(r_n)) lp.col_lower[s + n] = -r_n / s_scale;
    switch (states[k]) {
      case State::kOpen:
        velocity_row(n, 0.0, kInfinity);
        for (int u = n; u < n + per; ++u) fix(u);
        break;
      case State::kHeld:
        velocity_row(n, 0.0, 0.0);
        if (per == 2) fix(t);
        break;
      case State::kSticking:
        velocity_row(n, 0.0, 0.0);
        if (per == 1) break;
        velocity_row(t, 0.0, 0.0);
        {
          const double mu = p.contacts[k].mu;
          if (bounded(mu * r_n - forces[t])) friction_row(k, -1.0, -kInfinity, (mu * r_n - forces[t]) / s_scale);
          if (bounded(mu * r_n + forces[t])) friction_row(k, 1.0, -(mu * r_n + forces[t]) / s_scale, kInfinity);
        }
        break;
      case State::kSlidingForward:
        velocity_row(n, 0.0, 0.0);
        velocity_row(t, 0.0, kInfinity);
        friction_row(k, 1.0, 0.0, 0.0);
        break;
      case State::kSlidingBackward:
        velocity_row(n, 0.0, 0.0);
        velocity_row(t, -kInfinity, 0.0);
        friction_row(k, -1.0, 0.0, 0.0);
        break;
    }
  }
  AddL1Distance(lp, s, unknowns, Eigen::VectorXd::Zero(unknowns));
  return lp;
}

// Solves `lp` by CLP's primal simplex; its columns' values, or empty with a message.
std::vector<double> SolveLp(const Lp& lp, long long& iterations, std::string& message) {
  const CoinPackedMatrix matrix(true, lp.rows.data(), lp.cols.data(), lp.values.data(),
                                static_cast<CoinBigIndex>(lp.values.size()));
  ClpSimplex model;
  model.setLogLevel(0);
  model.loadProblem(matrix, lp.col_lower.data(), lp.col_upper.data(), lp.objective.data(), lp.row_lower.data(),
                    lp.row_upper.data());
  model.setPrimalTolerance(1e-10);
  model.setDualTolerance(1e-10);
  // The primal simplex: 2–10× fewer iterations and less time than the dual on these
  // models (an N = 500 opening: 1.1 s against 2.5 s for the motion).
  model.primal();
  iterations += model.numberIterations();
  if (model.isProvenOptimal()) return std::vector<double>(model.getColSolution(), model.getColSolution() + lp.col_lower.size());
  message = model.isProvenPrimalInfeasible() ? "infeasible" : "CLP stopped with status " + std::to_string(model.status());
  return {};
}

// Stage 1's forces meet its constraints to CLP's tolerance; stage 2 measures slacks in
// units of the response, a billion times smaller, so they are first put exactly on their
// pattern (the balance this disturbs is the kind of error stage 2 corrects anyway).
void ProjectOntoPattern(const ContactProblem& p, const std::vector<State>& states, Eigen::VectorXd& r) {
  const int per = p.UnknownsPerContact();
  for (int k = 0; k < p.NumContacts(); ++k) {
    const int n = per * k;
    if (states[k] == State::kOpen) {
      r.segment(n, per).setZero();
      continue;
    }
    if (states[k] != State::kHeld) r[n] = std::max(r[n], 0.0);
    if (per == 1) continue;
    const double limit = p.contacts[k].mu * r[n];
    switch (states[k]) {
      case State::kHeld: r[n + 1] = 0.0; break;
      case State::kSticking: r[n + 1] = std::clamp(r[n + 1], -limit, limit); break;
      case State::kSlidingForward: r[n + 1] = -limit; break;
      case State::kSlidingBackward: r[n + 1] = limit; break;
      case State::kOpen: break;
    }
  }
}

double ImpulseScale(const ContactProblem& p, const Eigen::VectorXd& reference, const Eigen::VectorXd& candidate) {
  for (const Eigen::VectorXd* v : {&reference, &candidate}) {
    double sum = 0.0;
    int count = 0;
    for (int k = 0; k < p.NumContacts(); ++k) {
      const double r_n = std::abs((*v)[p.UnknownsPerContact() * k]);
      if (r_n > 0.0) sum += r_n, ++count;
    }
    if (count > 0) return sum / count;
  }
  return 1.0;
}

}  // namespace

PatternSolution SolveOnPattern(const ContactProblem& problem, const Eigen::VectorXd& candidate,
                               const Eigen::VectorXd& reference, double velocity_scale,
                               double velocity_weight) {
  const auto sized = [&](const Eigen::VectorXd& v) { return v.size() == problem.NumUnknowns() && v.allFinite(); };
  if (!sized(candidate) || !sized(reference)) {
    throw std::invalid_argument("pattern LP: candidate and reference need " + std::to_string(problem.NumUnknowns()) +
                                " finite impulses");
  }
  if (!(velocity_scale > 0.0) || !std::isfinite(velocity_scale) || !(velocity_weight > 0.0) || !std::isfinite(velocity_weight)) {
    throw std::invalid_argument("pattern LP: the velocity scale and weight must be finite and > 0");
  }
  PatternSolution out;
  out.velocity_weight = velocity_weight;
  const double r_scale = ImpulseScale(problem, reference, candidate);
  const std::vector<State> states = PatternOf(problem, candidate, r_scale, velocity_scale, velocity_weight, out.pattern);
  std::string why;
  const std::vector<double> forces = SolveLp(BuildStaticLp(problem, states, reference, r_scale), out.iterations, why);
  if (forces.empty()) {
    out.message = "static forces of the pattern: " + why;
    return out;
  }
  out.impulses = Eigen::Map<const Eigen::VectorXd>(forces.data(), problem.NumUnknowns()) * r_scale;
  ProjectOntoPattern(problem, states, out.impulses);
  double s_scale = 0.0;
  const std::vector<double> change = SolveLp(BuildMotionLp(problem, states, out.impulses, velocity_scale, s_scale), out.iterations, why);
  if (change.empty()) {
    out.message = "motion of the pattern: " + why;
    return out;
  }
  out.impulses += Eigen::Map<const Eigen::VectorXd>(change.data() + problem.NumDofs(), problem.NumUnknowns()) * s_scale;
  out.found = true;
  return out;
}

}  // namespace unjam
