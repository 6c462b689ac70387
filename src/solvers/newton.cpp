// Semismooth Newton on the Alart–Curnier function (Alart & Curnier 1991), with UMFPACK.
//
// Per contact k, with ρ_k = 1/W_nn (as in the residual), posed velocity ũ = (ũ_n, u_t)
// and the augmented normal impulse ξ_n = r_n − ρ ũ_n:
//   Φ_n = r_n − max(0, ξ_n)
//   Φ_t = r_t − Π_[−μ ξ_n⁺, μ ξ_n⁺](r_t − ρ u_t)
// and for a held (bilateral) contact Φ_n = ρ ũ_n, Φ_t = r_t. Φ = 0 exactly when the
// Signorini–Coulomb law holds, the same solution set as the unjam residual's natural map.
//
// Why the augmented (velocity, impulse) system and not the Delassus matrix: a pressure
// bath couples every contact to the cell rate λ, so W = H M⁻¹ Hᵀ is dense; the
// augmented matrix
//     [ I     −M⁻¹Hᵀ ] [Δv]   [ 0 ]
//     [ B H     A    ] [Δr] = [ −Φ ]
// stays sparse (λ is one more column and row). A = ∂Φ/∂r, B = ∂Φ/∂ũ are 2×2 per contact.
//
// Why a proximal point: jammed frictional packings are hyperstatic, H has dependent rows,
// and the rows of sticking contacts (A = 0) make the Newton matrix singular. Newton
// therefore solves a sequence of proximal subproblems (Rockafellar's proximal point, the
// PROX method of Acary et al. 2018): the same law with ρũ replaced by
//     ρũ + ε (r − r_c),     r_c the current centre,
// i.e. W + (ε/ρ) I instead of W. Each subproblem is well posed; its Newton matrix is the
// one above with A + ε B/ρ, and its own merit makes the line search consistent. At a
// fixed point r = r_c the law itself holds. The centre moves after each subproblem; ε
// shrinks when subproblems are easy and grows when the line search fails. Self-stress
// components move only as far as the law demands, so a warm start (the static forces
// before a perturbation) picks the solution nearest to it.
//
// Globalisation. Semismooth Newton on a jammed packing from far away wanders: the active
// set (open, stick, slide) of hundreds of contacts changes at every step and the line
// search takes tiny steps (measured: 200 iterations without convergence on frictional
// perturbations). So NSGS, robust far from the solution, runs first to the warm-up
// tolerance, and Newton, fast near it, finishes. If Newton stalls (no halving of the
// residual in 15 iterations), NSGS resumes from Newton's best point to a 100× tighter
// warm-up, then Newton again (at most 4 rounds). Newton steps use Armijo backtracking on
// θ = ½‖Φ‖². Convergence is declared on the unjam residual, never on θ, and the best
// iterate seen is returned.
//
// Delassus form (ũ = W r + q, delassus_problem.hpp): the same system with H = I, M⁻¹Hᵀ = W
// and v_free = q, so that v = q + W r is ũ itself; the NSGS warm-up is NSGS on W.
#include "newton.hpp"
#include "deadline.hpp"
#include "matrix_form.hpp"
#include "nsgs.hpp"
#include "sparse_lu.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <Eigen/SparseCore>
#include <Eigen/UmfPackSupport>

#include "unjam/problem/kinematics.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

using solvers_internal::Deadline;
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

// The generalised Jacobian of Φ_k: Φ_k's derivatives in r_k (A) and in ũ_k (B).
struct LocalJacobian {
  Eigen::Matrix2d a = Eigen::Matrix2d::Identity();
  Eigen::Matrix2d b = Eigen::Matrix2d::Zero();
};

struct LocalValue {
  Eigen::Vector2d phi = Eigen::Vector2d::Zero();
  LocalJacobian jacobian;
};

LocalValue AlartCurnier(const ContactLaw& c, double rho, bool frictional, const Eigen::Vector2d& r,
                        const Eigen::Vector2d& u) {
  LocalValue out;
  LocalJacobian& J = out.jacobian;
  if (rho == 0.0) {  // no degrees of freedom on either side: the contact cannot act
    out.phi = Eigen::Vector2d(r[0], frictional ? r[1] : 0.0);
    return out;
  }
  if (c.kind == ConstraintKind::kBilateral) {
    out.phi = Eigen::Vector2d(rho * u[0], frictional ? r[1] : 0.0);
    J.a(0, 0) = 0.0;
    J.b(0, 0) = rho;
    return out;
  }
  const double xi_n = r[0] - rho * u[0];
  if (xi_n <= 0.0) {  // separating: r = 0
    out.phi = Eigen::Vector2d(r[0], frictional ? r[1] : 0.0);
    return out;
  }
  out.phi[0] = rho * u[0];
  J.a(0, 0) = 0.0;
  J.b(0, 0) = rho;
  if (!frictional) return out;
  const double tau = r[1] - rho * u[1];
  const double bound = c.mu * xi_n;
  if (bound > 0.0 && std::abs(tau) <= bound) {  // sticking (never with μ = 0: r_t = 0 slides)
    out.phi[1] = rho * u[1];
    J.a(1, 1) = 0.0;
    J.b(1, 1) = rho;
  } else {  // sliding: r_t = ±μ ξ_n
    const double s = tau > 0.0 ? 1.0 : -1.0;
    out.phi[1] = r[1] - s * bound;
    J.a(1, 0) = -s * c.mu;
    J.b(1, 0) = s * c.mu * rho;
  }
  return out;
}

// Fixed data of the problem: its matrix form (matrix_form.hpp; g = M⁻¹Hᵀ, or W) and the
// weights ρ of the residual.
struct Operators : solvers_internal::MatrixForm {
  std::vector<double> rho;
};

template <class Problem>
Operators MakeOperators(const Problem& p) {
  Operators op;
  static_cast<solvers_internal::MatrixForm&>(op) = solvers_internal::MatrixFormOf(p);
  for (int k = 0; k < p.NumContacts(); ++k) op.rho.push_back(ResidualWeight(p, k));
  return op;
}

struct Evaluation {
  Eigen::VectorXd phi;
  std::vector<LocalJacobian> local;
  double merit = 0.0;  // ½‖Φ‖²
};

// Φ of the proximal subproblem with centre `center` and weight ε (ε = 0: the law itself).
Evaluation Evaluate(const Operators& op, const Eigen::VectorXd& r, const Eigen::VectorXd& center,
                    double epsilon) {
  const int m = op.per_contact;
  const Eigen::VectorXd v = op.v_free + op.g * r;
  const Eigen::VectorXd u = op.h * v + op.offset;
  Evaluation e;
  e.phi.resize(r.size());
  e.local.resize(op.NumContacts());
  for (int k = 0; k < op.NumContacts(); ++k) {
    Eigen::Vector2d rk = Eigen::Vector2d::Zero(), uk = Eigen::Vector2d::Zero();
    for (int i = 0; i < m; ++i) {
      rk[i] = r[k * m + i];
      uk[i] = u[k * m + i];
      if (op.rho[k] > 0.0) uk[i] += epsilon / op.rho[k] * (r[k * m + i] - center[k * m + i]);
    }
    LocalValue lv = AlartCurnier(op.laws[k], op.rho[k], m == 2, rk, uk);
    for (int i = 0; i < m; ++i) e.phi[k * m + i] = lv.phi[i];
    e.local[k] = lv.jacobian;
  }
  e.merit = 0.5 * e.phi.squaredNorm();
  return e;
}

// The augmented Newton matrix of the subproblem. Every structural entry is emitted, zero
// or not, so that the sparsity pattern (and UMFPACK's symbolic analysis) never changes.
SparseMatrix NewtonMatrix(const Operators& op, const std::vector<LocalJacobian>& local,
                          double epsilon) {
  const int nd = op.NumDofs();
  const int nu = op.NumUnknowns();
  const int m = op.per_contact;
  Triplets t;
  t.reserve(nd + 3 * op.g.nonZeros() + 4 * nu);
  for (int i = 0; i < nd; ++i) t.emplace_back(i, i, 1.0);
  for (int col = 0; col < op.g.outerSize(); ++col) {
    for (SparseMatrix::InnerIterator it(op.g, col); it; ++it) {
      t.emplace_back(it.row(), nd + col, -it.value());
    }
  }
  // Row i of B H = Σ_j B_ij H_row(j), over the rows j of the same contact.
  for (int dof = 0; dof < op.h.outerSize(); ++dof) {  // column-major: outer = dof
    for (SparseMatrix::InnerIterator it(op.h, dof); it; ++it) {
      const int k = static_cast<int>(it.row()) / m;
      const int j = static_cast<int>(it.row()) % m;
      for (int i = 0; i < m; ++i)
        t.emplace_back(nd + k * m + i, dof, local[k].b(i, j) * it.value());
    }
  }
  for (int k = 0; k < op.NumContacts(); ++k) {
    const double shift = op.rho[k] > 0.0 ? epsilon / op.rho[k] : 0.0;
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < m; ++j) {
        t.emplace_back(nd + k * m + i, nd + k * m + j, local[k].a(i, j) + shift * local[k].b(i, j));
      }
    }
  }
  SparseMatrix k(nd + nu, nd + nu);
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

template <class Problem>
Eigen::VectorXd InitialImpulses(const Problem& p, const SolverGuess& guess) {
  if (guess.impulses.size() == p.NumUnknowns()) return guess.impulses;
  return Eigen::VectorXd::Zero(p.NumUnknowns());
}

constexpr double kArmijo = 1e-4;
constexpr int kMaxBacktracks = 30;
constexpr double kEpsilonFloor = 1e-14;
constexpr double kEpsilonMax = 1e2;
constexpr double kSubproblemReduction = 1e-3;  // a subproblem is solved when θ_ε falls by this
constexpr int kStallIterations = 15;  // Newton iterations without halving the best residual
constexpr int kProbeIterations = 30;  // Newton iterations of the probe from a warm start
constexpr int kMaxRounds = 4;         // NSGS warm-up + Newton rounds

struct Iterate {
  Eigen::VectorXd impulses;
  double residual = 0.0;
};

// One proximal Newton phase from `start`: until the tolerance, a stall, a failure or the
// budget. Returns the best iterate seen (the unjam residual can rise while θ_ε falls).
template <class Problem>
class NewtonPhase {
 public:
  NewtonPhase(const Problem& p, const SolverOptions& o, const Deadline& deadline)
      : p_(p), o_(o), deadline_(deadline), op_(MakeOperators(p)) {}

  Iterate Run(const Iterate& start, int& budget, std::string& failure) {
    Iterate best = start;
    Eigen::VectorXd r = start.impulses;
    Eigen::VectorXd center = r;
    double epsilon = EpsilonMin();
    Evaluation eval = Evaluate(op_, r, center, epsilon);
    double target = kSubproblemReduction * eval.merit;  // of the current subproblem
    int inner = 0;
    int since_progress = 0;
    double progress_mark = best.residual;
    while (best.residual > o_.tolerance && budget > 0 && since_progress < kStallIterations &&
           !deadline_.Passed()) {
      --budget;
      ++iterations_;
      ++since_progress;
      Eigen::VectorXd step;
      double alpha = 1.0;
      Evaluation trial;
      if (!Direction(eval, epsilon, step) ||
          !LineSearch(r, center, epsilon, step, eval, alpha, trial)) {
        // A stronger proximal term makes the subproblem better conditioned.
        if (epsilon >= kEpsilonMax) {
          failure = "line search failed at the largest proximal weight";
          break;
        }
        epsilon = std::min(epsilon * 100.0, kEpsilonMax);
        center = r;
        eval = Evaluate(op_, r, center, epsilon);
        target = kSubproblemReduction * eval.merit;
        inner = 0;
        continue;
      }
      r += alpha * step;
      eval = std::move(trial);
      ++inner;
      const double res = ComputeResidual(p_, r).residual;
      if (!std::isfinite(res)) {
        failure = "non-finite impulses";
        break;
      }
      if (res < best.residual) best = {r, res};
      if (best.residual <= 0.5 * progress_mark) {
        progress_mark = best.residual;
        since_progress = 0;
      }
      if (eval.merit <= target) {  // subproblem solved: move the centre
        if (inner <= 3) epsilon = std::max(epsilon * 0.1, EpsilonMin());
        center = r;
        eval = Evaluate(op_, r, center, epsilon);
        target = kSubproblemReduction * eval.merit;
        inner = 0;
      }
    }
    return best;
  }

  int iterations() const { return iterations_; }

 private:
  double EpsilonMin() const { return std::max(o_.newton.regularization, kEpsilonFloor); }

  bool Direction(const Evaluation& eval, double epsilon, Eigen::VectorXd& step) {
    const SparseMatrix k = NewtonMatrix(op_, eval.local, epsilon);
    if (!analysed_) {
      solvers_internal::ChooseOrdering(lu_, k.rows(), solvers_internal::kNewtonMetisRows);
      lu_.analyzePattern(k);
      analysed_ = true;
    }
    lu_.factorize(k);
    if (lu_.info() != Eigen::Success) {
      lu_.compute(k);  // the pivot order of the first analysis no longer fits
      if (lu_.info() != Eigen::Success) return false;
    }
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(k.rows());
    rhs.tail(op_.NumUnknowns()) = -eval.phi;
    step = lu_.solve(rhs).tail(op_.NumUnknowns());
    return step.allFinite();
  }

  // Armijo backtracking on θ_ε with the model decrease of a Newton step, 2θ_ε.
  bool LineSearch(const Eigen::VectorXd& r, const Eigen::VectorXd& center, double epsilon,
                  const Eigen::VectorXd& step, const Evaluation& eval, double& alpha,
                  Evaluation& trial) const {
    for (int b = 0; b < kMaxBacktracks; ++b, alpha *= 0.5) {
      trial = Evaluate(op_, r + alpha * step, center, epsilon);
      if (std::isfinite(trial.merit) && trial.merit <= (1.0 - 2.0 * kArmijo * alpha) * eval.merit)
        return true;
    }
    return false;
  }

  const Problem& p_;
  const SolverOptions& o_;
  const Deadline& deadline_;
  const Operators op_;
  Eigen::UmfPackLU<SparseMatrix> lu_;
  bool analysed_ = false;
  int iterations_ = 0;
};
SolveResult SolveWithNsgs(const ContactProblem& p, const SolverOptions& o,
                          const SolverGuess& guess) {
  return NsgsSolver().Solve(p, o, guess);
}
SolveResult SolveWithNsgs(const DelassusProblem& p, const SolverOptions& o,
                          const SolverGuess& guess) {
  return NsgsSolver().SolveDelassus(p, o, guess);
}

// NSGS from `start` to `tolerance`: the warm-up that brings Newton into its basin.
template <class Problem>
Iterate WarmUp(const Problem& p, const SolverOptions& o, const Deadline& deadline,
               const Iterate& start, double tolerance, SolveReport& report, int& sweeps) {
  SolverOptions warm_options = o;
  warm_options.tolerance = tolerance;
  warm_options.nsgs.max_sweeps = o.newton.warmup_max_sweeps;
  // What is left, kept positive (a passed deadline stops NSGS at its first check).
  warm_options.time_limit = std::max(deadline.SecondsLeft(), 1e-9);
  const SolveResult s = SolveWithNsgs(p, warm_options, {start.impulses, {}});
  report.contact_updates += s.report.contact_updates;
  sweeps += s.report.iterations;
  return {s.impulses, s.report.residual};
}

template <class Problem>
SolveResult SolveNewton(const Problem& p, const SolverOptions& options, const SolverGuess& guess,
                        const std::string& name);

// Nearly frictionless steps (every μ at most kNearlyFrictionless, a μ = 1e-8 packing): their
// solution is within μ of a frictionless one, while a frictional Newton pays for the
// stick/slide kinks of every contact (2.5–5× the iterations of μ = 0 per step,
// docs/performance.md). So the frictionless problem is solved first (half the unknowns, no
// kinks), and its answer with r_t = 0 starts the frictional one, which accepts it as it is
// when the frictional residual already meets the tolerance.
bool NearlyFrictionless(const ContactProblem& p) {
  if (!p.frictional || p.contacts.empty()) return false;
  for (const ProblemContact& c : p.contacts) {
    if (c.mu > kNearlyFrictionless) return false;
  }
  return true;
}

ContactProblem WithoutFriction(const ContactProblem& p) {
  ContactProblem q = p;
  q.frictional = false;
  q.inv_inertia.clear();
  q.free_spin.clear();
  for (ProblemContact& c : q.contacts) c.mu = 0.0;
  return q;
}

// The normal impulses of a frictional guess: the guess of WithoutFriction(p).
SolverGuess WithoutFriction(const ContactProblem& p, const SolverGuess& guess) {
  SolverGuess normal;
  if (guess.impulses.size() != p.NumUnknowns()) return normal;
  normal.impulses.resize(p.NumContacts());
  for (int k = 0; k < p.NumContacts(); ++k) normal.impulses[k] = guess.impulses[2 * k];
  return normal;
}

Iterate Start(const DelassusProblem& p, const SolverOptions&, const SolverGuess& guess,
              const std::string&, SolveReport&) {
  const Eigen::VectorXd r = InitialImpulses(p, guess);
  return {r, ComputeResidual(p, r).residual};
}

Iterate Start(const ContactProblem& p, const SolverOptions& options, const SolverGuess& guess,
              const std::string& name, SolveReport& report) {
  Iterate given{InitialImpulses(p, guess), 0.0};
  given.residual = ComputeResidual(p, given.impulses).residual;
  if (!NearlyFrictionless(p)) return given;
  const SolveResult frictionless =
      SolveNewton(WithoutFriction(p), options, WithoutFriction(p, guess), name);
  Iterate lifted{Eigen::VectorXd::Zero(p.NumUnknowns()), 0.0};
  for (int k = 0; k < p.NumContacts(); ++k) lifted.impulses[2 * k] = frictionless.impulses[k];
  lifted.residual = ComputeResidual(p, lifted.impulses).residual;
  report.contact_updates += frictionless.report.contact_updates;
  return lifted.residual < given.residual ? lifted : given;
}

// The whole method on either problem form (see the top of the file).
template <class Problem>
SolveResult SolveNewton(const Problem& p, const SolverOptions& options, const SolverGuess& guess,
                        const std::string& name) {
  SolveResult result;
  SolveReport& report = result.report;
  report.backend = name;
  const Deadline deadline(options.time_limit);
  const Iterate given = Start(p, options, guess, name, report);
  Iterate best = given;

  NewtonPhase<Problem> newton(p, options, deadline);
  int budget = options.newton.max_iterations;
  std::string failure;
  int sweeps = 0;
  // The probe: from a warm start (the static forces before a perturbation) Newton alone
  // often converges, where the NSGS warm-up would first spend most of the time (on a
  // quasi-static opening of N = 3000, 2.9 s to 8.2e-12 against 26.6 s to 3.9e-8 after
  // 245 000 sweeps; docs/performance.md). Where it stalls instead (most dynamic responses: Newton
  // from the static state wanders), the rounds below start from the warm start as if it
  // had not run, since they do better from there than from its stalled point.
  if (options.newton.warm_probe && guess.impulses.size() == p.NumUnknowns() &&
      best.residual > options.tolerance) {
    int probe_budget = std::min(budget, kProbeIterations);
    budget -= probe_budget;
    const Iterate probed = newton.Run(best, probe_budget, failure);
    budget += probe_budget;  // what the probe left
    if (probed.residual < best.residual) best = probed;
  }
  Iterate from = given;
  double warmup = options.newton.warmup_tolerance;
  for (int round = 0;
       round < kMaxRounds && best.residual > options.tolerance && budget > 0 && !deadline.Passed();
       ++round) {
    if (from.residual > warmup) {
      const Iterate warmed = WarmUp(p, options, deadline, from, warmup, report, sweeps);
      if (warmed.residual < from.residual) from = warmed;
    }
    failure.clear();
    const Iterate polished = newton.Run(from, budget, failure);
    if (polished.residual < from.residual) from = polished;
    if (from.residual < best.residual) best = from;
    // Not there yet: warm up further from this round's point, past where Newton stalled.
    warmup = std::min(warmup, from.residual) * 1e-2;
  }
  result.impulses = best.impulses;
  report.iterations = newton.iterations();
  report.residual = best.residual;
  if (!std::isfinite(best.residual)) {
    report.status = SolveStatus::kNumericalFailure;
    report.message = "non-finite impulses";
  } else if (best.residual <= options.tolerance) {
    report.status = SolveStatus::kConverged;
  } else if (!failure.empty()) {
    report.status = SolveStatus::kNumericalFailure;
    report.message = failure;
  } else if (deadline.Passed()) {
    report.status = SolveStatus::kIterationLimit;
    report.message = solvers_internal::TimeLimitMessage(options.time_limit);
  } else {
    report.status = SolveStatus::kIterationLimit;
    report.message = "Newton stalled or reached its iteration limit before the tolerance";
  }
  if (sweeps > 0)
    report.message +=
        (report.message.empty() ? "" : "; ") + std::to_string(sweeps) + " NSGS warm-up sweeps";
  return result;
}

}  // namespace

SolveResult NewtonSolver::DoSolve(const ContactProblem& p, const SolverOptions& options,
                                  const SolverGuess& guess) {
  return SolveNewton(p, options, guess, Name());
}

SolveResult NewtonSolver::DoSolveDelassus(const DelassusProblem& p, const SolverOptions& options,
                                          const SolverGuess& guess) {
  return SolveNewton(p, options, guess, Name());
}

}  // namespace unjam
