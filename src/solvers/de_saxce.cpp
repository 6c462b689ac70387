// The De Saxcé fixed point (Acary, Cadoux, Lemaréchal, Marcote 2011; METHOD.md "Comparing
// solvers"): the exact Coulomb law through a sequence of convex problems.
//
//   s⁰ = Shift(ũ(r⁰))                               (r⁰: the warm start, or 0)
//   repeat: rʲ⁺¹ = argmin_{r ∈ K} ½ rᵀ W r + (q + sʲ)ᵀ r     (a library solves this)
//           sʲ⁺¹ = Shift(ũ(rʲ⁺¹)) = (μ |u_t(rʲ⁺¹)|, 0)
// until the unjam residual of rʲ⁺¹ meets the tolerance. A fixed point is a solution of the
// exact law. Convergence is not guaranteed (the map is a contraction for small μ); in a
// static state every contact sticks (u_t = 0), the shift vanishes and one solve suffices.
//
// Inner tolerance. A convex solve need only be as accurate as the shift it uses is right,
// so the inner tolerance follows the last move of the shift (ShiftChange, in residual
// units) and tightens with it, down to a tenth of the outer tolerance once the shift stops
// moving. Without friction, or for the relaxation, the shift is zero and the first solve
// is already tight.
//
// First shift. From a warm start, the slip of the warm start; from cold, zero (the free
// velocity's slip is mostly stopped by the contacts). Measured from cold (tolerance 1e-10):
// starting from the free slip stalls the fixed point near 5e-5 on the N = 100 pile;
// solving the first problem loosely (1e-3 or 1e-6) stalls it near 4e-10 (ipopt) and 1e-8
// (nlopt) on the N = 500, μ = 0.5 packing, wandering among sliding states; a tight first
// solve with zero shift finds both static states in one solve.
//
// After each solve, contacts the natural map finds open are zeroed if that lowers the
// convex residual (ConvexLaw::ZeroOpenContacts), and the best iterate by the true residual
// is kept. The loop stops at the tolerance, at options.de_saxce.max_outer_iterations
// convex solves, when a library reports a failure, when the same tight problem brings no
// improvement (the library's accuracy limit), or after 10 solves without halving the
// residual.
#include "de_saxce.hpp"
#include "deadline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/SparseCholesky>

#include "unjam/problem/kinematics.hpp"
#include "unjam/solvers/pattern_polish.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

ContactLayout LayoutOf(const ContactProblem& p) {
  ContactLayout layout;
  layout.per_contact = p.UnknownsPerContact();
  layout.frictional = p.frictional;
  for (int k = 0; k < p.NumContacts(); ++k) {
    layout.laws.push_back({p.contacts[k].mu, p.contacts[k].kind});
    layout.diagonal.push_back(DelassusDiagonal(p, k));
  }
  return layout;
}

ContactLayout LayoutOf(const DelassusProblem& p) {
  ContactLayout layout;
  layout.per_contact = 2;
  layout.frictional = true;
  layout.laws = p.laws;
  for (int k = 0; k < p.NumContacts(); ++k) {
    layout.diagonal.emplace_back(p.w.coeff(2 * k, 2 * k), p.w.coeff(2 * k + 1, 2 * k + 1));
  }
  return layout;
}

namespace {
double LargestMagnitude(const Eigen::SparseMatrix<double>& m) {
  double largest = 0.0;
  for (int col = 0; col < m.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(m, col); it; ++it)
      largest = std::max(largest, std::abs(it.value()));
  }
  return largest;
}
}  // namespace

std::string AsymmetryOf(const DelassusProblem& p) {
  const Eigen::SparseMatrix<double> transpose = p.w.transpose();
  const double largest = LargestMagnitude(p.w);
  const double worst = LargestMagnitude(p.w - transpose);
  if (worst <= kSymmetryTolerance * largest) return "";
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "W is not symmetric (max |W - W^T| = %.3g, %.3g of max |W|): ", worst,
                worst / largest);
  return std::string(buf) +
         "the De Saxcé fixed point minimises 1/2 r^T W r + (q + s)^T r, which needs a symmetric W "
         "(docs/backends.md)";
}

std::string IndefinitenessOf(const DelassusProblem& p) {
  const Eigen::SparseMatrix<double> transpose = p.w.transpose();
  Eigen::SparseMatrix<double> shifted = 0.5 * (p.w + transpose);
  const double largest = LargestMagnitude(shifted);
  if (largest == 0.0) return "";
  Eigen::SparseMatrix<double> identity(shifted.rows(), shifted.cols());
  identity.setIdentity();
  shifted += kDefinitenessTolerance * largest * identity;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(shifted);
  int negative = 0;
  double lowest = 0.0;
  if (ldlt.info() == Eigen::Success) {
    const Eigen::VectorXd d = ldlt.vectorD();
    for (Eigen::Index i = 0; i < d.size(); ++i) {
      if (d[i] < 0.0) ++negative;
      lowest = std::min(lowest, d[i]);
    }
    if (negative == 0) return "";
  }
  char buf[200];
  std::snprintf(
      buf, sizeof buf,
      "W is not positive semidefinite (the LDL^T factorisation of (W + W^T)/2 + %.0e max|W| I "
      "has %d negative pivots, the lowest %.3g): ",
      kDefinitenessTolerance, negative, lowest);
  return std::string(buf) +
         "1/2 r^T W r + (q + s)^T r is then not convex and the De Saxcé fixed point stalls among "
         "its "
         "local minima; nsgs, newton and lemke do not need a convex W (docs/backends.md)";
}

std::string NotConvexOf(const DelassusProblem& p) {
  const std::string asymmetry = AsymmetryOf(p);
  return asymmetry.empty() ? IndefinitenessOf(p) : asymmetry;
}

SolveResult Unsupported(const DelassusProblem& p, const std::string& backend,
                        const std::string& why) {
  SolveResult result;
  result.impulses = Eigen::VectorXd::Zero(p.NumUnknowns());
  result.report.backend = backend;
  result.report.status = SolveStatus::kUnsupported;
  result.report.message = "backend '" + backend + "' refuses this problem: " + why;
  return result;
}

namespace {

template <class Problem>
std::vector<double> Weights(const Problem& p) {
  std::vector<double> rho(p.NumContacts());
  for (int k = 0; k < p.NumContacts(); ++k) rho[k] = ResidualWeight(p, k);
  return rho;
}

bool IsFrictionalUnilateral(const ContactLayout& layout, int k) {
  return layout.frictional && layout.laws[k].kind == ConstraintKind::kUnilateral;
}

}  // namespace

ConvexLaw::ConvexLaw(const ContactProblem& p) : layout_(LayoutOf(p)), rho_(Weights(p)) {
  fallback_scale_ = ComputeResidual(p, Eigen::VectorXd::Zero(p.NumUnknowns())).scale;
}

ConvexLaw::ConvexLaw(const DelassusProblem& p) : layout_(LayoutOf(p)), rho_(Weights(p)) {
  fallback_scale_ = ComputeResidual(p, Eigen::VectorXd::Zero(p.NumUnknowns())).scale;
}

Eigen::Vector2d ConvexLaw::Local(const Eigen::VectorXd& x, int k) const {
  const int m = layout_.per_contact;
  return Eigen::Vector2d(x[k * m], m == 2 ? x[k * m + 1] : 0.0);
}

Eigen::VectorXd ConvexLaw::Shift(const Eigen::VectorXd& velocity) const {
  Eigen::VectorXd s = Eigen::VectorXd::Zero(layout_.NumUnknowns());
  for (int k = 0; k < layout_.NumContacts(); ++k) {
    if (IsFrictionalUnilateral(layout_, k))
      s[2 * k] = layout_.laws[k].mu * std::abs(velocity[2 * k + 1]);
  }
  return s;
}

double ConvexLaw::Scale(const Eigen::VectorXd& impulses) const {
  double sum = 0.0;
  for (int k = 0; k < layout_.NumContacts(); ++k) sum += std::abs(Local(impulses, k)[0]);
  return sum > 0.0 ? sum / layout_.NumContacts() : fallback_scale_;
}

// r_k − ρ_k (ũ_k + s_k): the point the natural map projects.
Eigen::Vector2d ConvexLaw::MapArgument(const Eigen::VectorXd& impulses,
                                       const Eigen::VectorXd& velocity,
                                       const Eigen::VectorXd& shift, int k) const {
  return Local(impulses, k) - rho_[k] * (Local(velocity, k) + Local(shift, k));
}

double ConvexLaw::Residual(const Eigen::VectorXd& impulses, const Eigen::VectorXd& velocity,
                           const Eigen::VectorXd& shift) const {
  if (layout_.NumContacts() == 0) return 0.0;
  double worst = 0.0;
  for (int k = 0; k < layout_.NumContacts(); ++k) {
    const Eigen::Vector2d r = Local(impulses, k);
    const Eigen::Vector2d z = MapArgument(impulses, velocity, shift, k);
    double e = 0.0;
    if (layout_.laws[k].kind == ConstraintKind::kBilateral) {
      e = std::hypot(r[0] - z[0], r[1]);  // ρ ũ_n, and r_t = 0
    } else if (!layout_.frictional) {
      e = std::abs(r[0] - std::max(0.0, z[0]));
    } else {
      e = (r - ProjectOnCone(z, layout_.laws[k].mu)).norm();
    }
    worst = std::max(worst, e);
  }
  return worst / Scale(impulses);
}

double ConvexLaw::ShiftChange(const Eigen::VectorXd& impulses, const Eigen::VectorXd& before,
                              const Eigen::VectorXd& after) const {
  double worst = 0.0;
  for (int k = 0; k < layout_.NumContacts(); ++k) {
    worst = std::max(worst, rho_[k] * std::abs(Local(after, k)[0] - Local(before, k)[0]));
  }
  return worst / Scale(impulses);
}

Eigen::VectorXd ConvexLaw::ZeroOpenContacts(const Eigen::VectorXd& impulses,
                                            const Eigen::VectorXd& velocity,
                                            const Eigen::VectorXd& shift) const {
  Eigen::VectorXd out = impulses;
  const int m = layout_.per_contact;
  for (int k = 0; k < layout_.NumContacts(); ++k) {
    if (layout_.laws[k].kind == ConstraintKind::kBilateral) continue;
    const Eigen::Vector2d z = MapArgument(impulses, velocity, shift, k);
    const bool open =
        layout_.frictional ? ProjectOnCone(z, layout_.laws[k].mu).isZero(0.0) : z[0] <= 0.0;
    if (open) out.segment(k * m, m).setZero();
  }
  return out;
}

namespace {

constexpr double kInnerSafety = 0.1;    // the tightest inner tolerance, × the outer one
constexpr double kShiftFollow = 0.1;    // inner tolerance × the last move of the shift
constexpr double kLoosestInner = 1e-3;  // looser convex solves are wasted
constexpr int kStallIterations = 10;    // outer iterations without halving the residual

// ũ = W r + q of either form.
Eigen::VectorXd Posed(const ContactProblem& p, const Eigen::VectorXd& r) {
  return PosedContactVelocity(p, r);
}
Eigen::VectorXd Posed(const DelassusProblem& p, const Eigen::VectorXd& r) { return p.w * r + p.q; }

struct Iterate {
  Eigen::VectorXd impulses;
  double residual = 0.0;
};

double InnerTolerance(const SolverOptions& o, double shift_change) {
  return std::max(kInnerSafety * o.tolerance, std::min(kShiftFollow * shift_change, kLoosestInner));
}

// The step's impulses, with the open contacts zeroed if that lowers the convex residual.
template <class Problem>
Iterate Polished(const Problem& p, const ConvexLaw& law, const Eigen::VectorXd& impulses,
                 const Eigen::VectorXd& shift) {
  const Eigen::VectorXd u = Posed(p, impulses);
  const Eigen::VectorXd zeroed = law.ZeroOpenContacts(impulses, u, shift);
  const Eigen::VectorXd u_zeroed = Posed(p, zeroed);
  const bool better = law.Residual(zeroed, u_zeroed, shift) <= law.Residual(impulses, u, shift);
  const Eigen::VectorXd& r = better ? zeroed : impulses;
  return {r, ComputeResidual(p, r).residual};
}

template <class Problem>
Eigen::VectorXd InitialImpulses(const Problem& p, const SolverGuess& guess) {
  if (guess.impulses.size() == p.NumUnknowns() && guess.impulses.allFinite()) return guess.impulses;
  return Eigen::VectorXd::Zero(p.NumUnknowns());
}

// Why the loop stopped, when it stopped short of the tolerance.
struct Outcome {
  SolveStatus status = SolveStatus::kIterationLimit;
  std::string message;
};

std::string Number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

template <class Problem>
SolveResult Finish(const Problem& p, const Iterate& chosen, const Outcome& outcome, int solves,
                   int library_iterations, const SolverOptions& o, const std::string& backend,
                   const ConvexStepSolver& step) {
  SolveResult result;
  result.impulses = chosen.impulses;
  SolveReport& report = result.report;
  report.backend = backend;
  report.iterations = solves;
  report.residual = chosen.residual;
  if (!std::isfinite(chosen.residual)) {
    report.status = SolveStatus::kNumericalFailure;
    report.message = "non-finite impulses";
  } else if (chosen.residual <= o.tolerance) {
    report.status = SolveStatus::kConverged;
  } else {
    report.status = outcome.status;
    report.message = outcome.message;
  }
  if (p.NumContacts() > 0) {
    const std::string count = std::to_string(library_iterations) + " " + step.IterationName();
    report.message += (report.message.empty() ? "" : "; ") + count;
  }
  return result;
}

// Why the fixed point ends on its contact pattern: an interior point or a bounded L-BFGS
// stops just below the tolerance it is given, and the residual's ρ = 1/W_nn does not see
// every error that matters. At a mass ratio of 1e6 (problems/hard/heavy-on-light.unjam)
// their converged answers had the heavy disk's contacts 1e-6 off, and nlopt's time steps
// at rest, each `converged`, created energy 15 times the stability check's bound over 10⁵
// steps (docs/stability.md). Solved exactly on its pattern (pattern_polish.hpp: one sparse
// factorisation per round, far less than the convex solves) the answer is exact where its
// pattern is right. Only a converged answer: one that stopped short says so, as it is
// (SolveStatic still polishes it). Polishing those too turned the wedge's reported steps
// (problems/hard/wedge.unjam) into `converged` ones just below the tolerance, and over 10⁵
// steps at rest the disk then sank 3–6e-5 into the walls: a silent failure where there was
// an honest one. A Delassus-form problem has no bodies to pose that system: as it is.
SolveResult EndOnPattern(const ContactProblem& p, const SolveResult& answer, double tolerance) {
  return answer.report.converged() ? PolishOnPattern(p, answer, tolerance) : answer;
}
SolveResult EndOnPattern(const DelassusProblem&, const SolveResult& answer, double) {
  return answer;
}

// One convex solve without shift: the relaxed model's answer is returned whatever its
// residual against the exact law.
template <class Problem>
SolveResult SolveRelaxation(const Problem& p, const SolverOptions& o, const SolverGuess& guess,
                            const std::string& backend, ConvexStepSolver& step) {
  const ConvexLaw law(p);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.NumUnknowns());
  if (p.NumContacts() == 0) return Finish(p, {zero, 0.0}, {}, 0, 0, o, backend, step);
  const ConvexStep s =
      step.Solve(zero, InitialImpulses(p, guess), kInnerSafety * o.tolerance, o.time_limit);
  if (!s.impulses.allFinite()) {
    return Finish(p, {s.impulses, std::numeric_limits<double>::quiet_NaN()}, {}, 1, s.iterations, o,
                  backend, step);
  }
  const Iterate solution = Polished(p, law, s.impulses, zero);
  const double own = law.Residual(solution.impulses, Posed(p, solution.impulses), zero);
  Outcome outcome;
  if (!s.solved) {
    outcome = {s.failure, s.library_status};
  } else if (own <= o.tolerance) {
    outcome = {SolveStatus::kRelaxedModel, "convex relaxation solved (its own residual " +
                                               Number(own) +
                                               "); a different model from the exact Coulomb law, "
                                               "against which the residual is reported"};
  } else {
    outcome = {SolveStatus::kIterationLimit,
               "convex relaxation not solved to the tolerance (its own residual " + Number(own) +
                   ", " + s.library_status + ")"};
  }
  return Finish(p, solution, outcome, 1, s.iterations, o, backend, step);
}

template <class Problem>
SolveResult FixedPoint(const Problem& p, const SolverOptions& o, const SolverGuess& guess,
                       const std::string& backend, ConvexStepSolver& step) {
  if (o.de_saxce.convex_relaxation) return SolveRelaxation(p, o, guess, backend, step);
  const ConvexLaw law(p);
  Iterate best{InitialImpulses(p, guess), 0.0};
  best.residual = ComputeResidual(p, best.impulses).residual;
  Eigen::VectorXd r = best.impulses;
  const bool warm = !r.isZero(0.0);  // the first shift: see the top of the file
  Eigen::VectorXd shift = warm ? law.Shift(Posed(p, r)) : Eigen::VectorXd::Zero(p.NumUnknowns());
  Eigen::VectorXd previous_shift = Eigen::VectorXd::Zero(p.NumUnknowns());

  Outcome outcome{SolveStatus::kIterationLimit,
                  "outer iteration limit of the De Saxcé fixed point"};
  int solves = 0;
  int library_iterations = 0;
  int since_progress = 0;
  double progress_mark = best.residual;
  const solvers_internal::Deadline deadline(o.time_limit);
  while (best.residual > o.tolerance && solves < o.de_saxce.max_outer_iterations) {
    if (deadline.Passed()) {
      outcome = {SolveStatus::kIterationLimit, solvers_internal::TimeLimitMessage(o.time_limit)};
      break;
    }
    const double inner = InnerTolerance(o, law.ShiftChange(r, previous_shift, shift));
    const double best_before = best.residual;
    const ConvexStep s = step.Solve(shift, r, inner, deadline.SecondsLeft());
    ++solves;
    library_iterations += s.iterations;
    if (!s.impulses.allFinite()) {
      outcome = {SolveStatus::kNumericalFailure, s.library_status + ": non-finite impulses"};
      break;
    }
    const Iterate polished = Polished(p, law, s.impulses, shift);
    r = polished.impulses;
    if (polished.residual < best.residual) best = polished;
    if (!s.solved) {
      outcome = {s.failure, s.library_status + " in convex solve " + std::to_string(solves)};
      if (deadline.Passed())
        outcome = {SolveStatus::kIterationLimit, solvers_internal::TimeLimitMessage(o.time_limit)};
      break;
    }
    previous_shift = shift;
    shift = law.Shift(Posed(p, r));
    // The same convex problem again, as tight as before, after a solve that did not help:
    // the library's accuracy, not the shift, is the limit.
    const double tightest = kInnerSafety * o.tolerance;
    if (!step.Proximal() && inner <= tightest &&
        InnerTolerance(o, law.ShiftChange(r, previous_shift, shift)) <= tightest &&
        !(best.residual < best_before)) {
      outcome = {SolveStatus::kIterationLimit,
                 "the convex solves stopped improving with the shift settled (the library's "
                 "accuracy limit)"};
      break;
    }
    if (best.residual <= 0.5 * progress_mark) {
      progress_mark = best.residual;
      since_progress = 0;
    } else if (++since_progress >= kStallIterations) {
      outcome = {SolveStatus::kIterationLimit,
                 "De Saxcé fixed point stalled (no halving of the residual in " +
                     std::to_string(kStallIterations) + " convex solves)"};
      break;
    }
  }
  SolveResult result = Finish(p, best, outcome, solves, library_iterations, o, backend, step);
  // A warm start that met the tolerance without a convex solve is the caller's answer and
  // is returned as it came: on the 3 200-contact pile at rest, polishing such a warm start
  // cost 1.2–2 s per step and lowered nothing (7e-11 stayed 7e-11).
  return solves > 0 ? EndOnPattern(p, result, o.tolerance) : result;
}

}  // namespace

SolveResult SolveByDeSaxceFixedPoint(const ContactProblem& p, const SolverOptions& o,
                                     const SolverGuess& guess, const std::string& backend,
                                     ConvexStepSolver& step) {
  return FixedPoint(p, o, guess, backend, step);
}

SolveResult SolveByDeSaxceFixedPoint(const DelassusProblem& p, const SolverOptions& o,
                                     const SolverGuess& guess, const std::string& backend,
                                     ConvexStepSolver& step) {
  return FixedPoint(p, o, guess, backend, step);
}

}  // namespace unjam
