// The convex step of the De Saxcé fixed point (de_saxce.hpp) as a bound-constrained QP for
// NLopt, matrix-free.
//
// Edge variables. A 2D Coulomb cone is spanned by its two edges e± = (1, ±μ):
//     r_k = a_k e₊ + b_k e₋,   a_k, b_k ≥ 0      ⇔   |r_t| ≤ μ r_n,
// so the cone constraints become bounds. A frictionless contact (or μ = 0) keeps one
// variable r_n ≥ 0, a held contact one free variable r_n (r_t = 0). With r = E y,
//     minimise  ½ yᵀ Eᵀ W E y + Eᵀ(q + s)·y   over y ≥ l,
// gradient Eᵀ(W r + q + s) = Eᵀ(ũ + s). For a body problem W is never formed: ũ = H (v_free
// + M⁻¹ Hᵀ r) + offset is two sparse products (a pressure bath's cell rate is one more column
// of H, which would make W dense). For a Delassus-form problem (SolveDelassus) the products
// are with the sparse W as given, which must be symmetric (de_saxce.hpp, AsymmetryOf). Each
// column of E is divided by √(e·W e) ≈ √(W_nn + μ² W_tt) (Jacobi scaling, exact for an
// uncoupled block), so the Hessian has a (nearly) constant diagonal.
//
// Accuracy. Near the minimum the objective changes by ‖g‖² while its value is O(‖g₀‖²):
// with an objective in absolute terms, a line search can resolve the gradient only to
// √ε ≈ 1e-8 of where it started, and Luksan's L-BFGS also stops at a projected gradient of
// 1e-8 (absolute). So the objective of each NLopt run is measured from the run's start y₀,
//     f(y) = σ (g₀·d + ½ dᵀ Eᵀ W E d),   d = y − y₀,   σ = 1 / |P g₀|∞,
// computed from d alone (no cancellation), and when a run stops short of the tolerance a
// new run starts from the best point with fresh σ and y₀: every run can gain up to eight
// digits. Runs stop when our own measure (ConvexLaw::Residual) meets the inner tolerance
// (nlopt_force_stop), when the evaluations run out, or when a run brings no improvement.
#include "nlopt_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlopt.h>

#include <Eigen/SparseCore>

#include "de_saxce.hpp"
#include "deadline.hpp"
#include "unjam/problem/kinematics.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// Stored L-BFGS pairs. NLopt's default (~1e6 / n, 650 here) costs O(n) each per iteration,
// far more than the two sparse products; 5, 10, 20 or 50 pairs take about as many
// evaluations on the bundled N = 500 packings (measured).
constexpr unsigned kLbfgsMemory = 20;
// A run ends when its objective stops moving (relative change, two iterations in a row for
// L-BFGS): its digits are spent, and the next run starts afresh from the best point. CCSA
// never ends a run by itself otherwise.
constexpr double kRunFunctionTolerance = 1e-12;

// The variables of one contact: its two edge weights, r_n alone (≥ 0, or free for a held
// contact), or none if the contact has no degrees of freedom on either side.
enum class Variables { kNone, kEdges, kNormal, kFreeNormal };

// r = E y. The unit of y_k is unit_k = S / (kResolution √(e·W e)): the √ is the Jacobi
// scaling, and kResolution keeps the impulses NLopt can tell from 0 far below any tolerance
// (Luksan's L-BFGS sets every variable within 1e-8 of its bound (absolute) onto it).
struct EdgeMap {
  SparseMatrix e;               // NumUnknowns × variables
  std::vector<double> lower;    // per variable
  std::vector<Variables> kind;  // per contact
  std::vector<int> first;       // per contact: its first variable
  std::vector<double> unit;     // per contact
};

constexpr double kResolution = 1e6;
constexpr double kBoundSnap = 1e-8;  // Luksan's eps9, for bounds of magnitude ≤ 1

EdgeMap MakeEdgeMap(const ContactLayout& p, double impulse_scale) {
  EdgeMap map;
  const int m = p.per_contact;
  std::vector<Eigen::Triplet<double>> t;
  map.kind.assign(p.NumContacts(), Variables::kNone);
  map.first.assign(p.NumContacts(), -1);
  map.unit.assign(p.NumContacts(), 0.0);
  for (int k = 0; k < p.NumContacts(); ++k) {
    const ContactLaw& c = p.laws[k];
    const Eigen::Vector2d& w = p.diagonal[k];
    const bool edges = p.frictional && c.kind == ConstraintKind::kUnilateral && c.mu > 0.0;
    const double curvature = edges ? w[0] + c.mu * c.mu * w[1] : w[0];
    if (!(curvature > 0.0)) continue;
    map.kind[k] = edges ? Variables::kEdges
                        : (c.kind == ConstraintKind::kBilateral ? Variables::kFreeNormal
                                                                : Variables::kNormal);
    map.first[k] = static_cast<int>(map.lower.size());
    map.unit[k] = impulse_scale / (kResolution * std::sqrt(curvature));
    const double lower = map.kind[k] == Variables::kFreeNormal ? -HUGE_VAL : 0.0;
    for (double sign : edges ? std::vector<double>{1.0, -1.0} : std::vector<double>{0.0}) {
      const int column = static_cast<int>(map.lower.size());
      t.emplace_back(k * m, column, map.unit[k]);
      if (edges) t.emplace_back(k * m + 1, column, sign * c.mu * map.unit[k]);
      map.lower.push_back(lower);
    }
  }
  map.e.resize(p.NumUnknowns(), static_cast<Eigen::Index>(map.lower.size()));
  map.e.setFromTriplets(t.begin(), t.end());
  return map;
}

// y of impulses r (projected on the cones first, so that the edge weights are ≥ 0).
Eigen::VectorXd EdgeValues(const ContactLayout& p, const EdgeMap& map, const Eigen::VectorXd& r) {
  Eigen::VectorXd y(map.lower.size());
  const int m = p.per_contact;
  for (int k = 0; k < p.NumContacts(); ++k) {
    const int i = map.first[k];
    switch (map.kind[k]) {
      case Variables::kNone: break;
      case Variables::kFreeNormal: y[i] = r[k * m] / map.unit[k]; break;
      case Variables::kNormal: y[i] = std::max(0.0, r[k * m]) / map.unit[k]; break;
      case Variables::kEdges: {
        const double mu = p.laws[k].mu;
        const Eigen::Vector2d rc = ProjectOnCone(Eigen::Vector2d(r[k * m], r[k * m + 1]), mu);
        y[i] = 0.5 * (rc[0] + rc[1] / mu) / map.unit[k];
        y[i + 1] = 0.5 * (rc[0] - rc[1] / mu) / map.unit[k];
        break;
      }
    }
  }
  return y;
}

struct NloptDeleter {
  void operator()(nlopt_opt o) const { nlopt_destroy(o); }
};
using NloptHandle = std::unique_ptr<std::remove_pointer_t<nlopt_opt>, NloptDeleter>;

// Products with W and the posed velocity ũ = W r + q, of either form.
class Delassus {
 public:
  virtual ~Delassus() = default;
  virtual Eigen::VectorXd Apply(const Eigen::VectorXd& r) const = 0;  // W r
  virtual Eigen::VectorXd Posed(const Eigen::VectorXd& r) const = 0;  // W r + q
};

// Body form: W is never formed, ũ = H (v_free + M⁻¹ Hᵀ r) + offset.
class BodyDelassus final : public Delassus {
 public:
  explicit BodyDelassus(const ContactProblem& p)
      : h_(AssembleJacobian(p)), ht_(h_.transpose()), inverse_mass_(InverseMassDiagonal(p)),
        free_velocity_(FreeVelocityVector(p)), offset_(VelocityOffset(p)) {}
  Eigen::VectorXd Apply(const Eigen::VectorXd& r) const override {
    return h_ * inverse_mass_.cwiseProduct(ht_ * r);
  }
  Eigen::VectorXd Posed(const Eigen::VectorXd& r) const override {
    return h_ * (free_velocity_ + inverse_mass_.cwiseProduct(ht_ * r)) + offset_;
  }

 private:
  const SparseMatrix h_, ht_;
  const Eigen::VectorXd inverse_mass_, free_velocity_, offset_;
};

// Delassus form: the sparse W as given (symmetric, AsymmetryOf).
class StoredDelassus final : public Delassus {
 public:
  explicit StoredDelassus(const DelassusProblem& p) : p_(p) {}
  Eigen::VectorXd Apply(const Eigen::VectorXd& r) const override { return p_.w * r; }
  Eigen::VectorXd Posed(const Eigen::VectorXd& r) const override { return p_.w * r + p_.q; }

 private:
  const DelassusProblem& p_;
};

class NloptStep;

// One NLopt run: the objective measured from y₀, and the best point of the run.
struct Run {
  const NloptStep* step = nullptr;
  const Eigen::VectorXd* shift = nullptr;
  nlopt_opt opt = nullptr;
  double tolerance = 0.0;
  Eigen::VectorXd y0, r0, u0, g0;  // start, its impulses, posed velocities and gradient
  double sigma = 1.0;
  Eigen::VectorXd best_y;
  double best_residual = 0.0;
  bool reached = false;
  int evaluations = 0;
};

double Objective(unsigned n, const double* x, double* gradient, void* data);

class NloptStep final : public ConvexStepSolver {
 public:
  template <class Problem>
  NloptStep(const Problem& p, const SolverOptions& o, double impulse_scale,
            std::unique_ptr<const Delassus> delassus)
      : layout_(LayoutOf(p)), o_(o), law_(p), map_(MakeEdgeMap(layout_, impulse_scale)),
        w_(std::move(delassus)) {}

  ConvexStep Solve(const Eigen::VectorXd& shift, const Eigen::VectorXd& start, double tolerance,
                   double time_limit) override;
  std::string IterationName() const override { return "NLopt evaluations"; }

  // W r, matrix-free.
  Eigen::VectorXd ApplyDelassus(const Eigen::VectorXd& r) const { return w_->Apply(r); }
  const EdgeMap& map() const { return map_; }
  const ConvexLaw& law() const { return law_; }

 private:
  void StartRun(Run& run, const Eigen::VectorXd& y0) const;
  nlopt_result RunOnce(Run& run, int evaluations_left, double seconds_left) const;

  const ContactLayout layout_;
  const SolverOptions& o_;
  const ConvexLaw law_;
  const EdgeMap map_;
  const std::unique_ptr<const Delassus> w_;
};

double Objective(unsigned n, const double* x, double* gradient, void* data) {
  Run& run = *static_cast<Run*>(data);
  const NloptStep& step = *run.step;
  ++run.evaluations;
  const Eigen::VectorXd d = Eigen::Map<const Eigen::VectorXd>(x, n) - run.y0;
  const Eigen::VectorXd rd = step.map().e * d;
  const Eigen::VectorXd ud = step.ApplyDelassus(rd);
  const Eigen::VectorXd g = run.g0 + step.map().e.transpose() * ud;
  if (gradient != nullptr) Eigen::Map<Eigen::VectorXd>(gradient, n) = run.sigma * g;
  // Our own measure of the convex step, on every evaluation (it costs O(N_c)).
  const double residual = step.law().Residual(run.r0 + rd, run.u0 + ud, *run.shift);
  if (residual < run.best_residual) {
    run.best_residual = residual;
    run.best_y = Eigen::Map<const Eigen::VectorXd>(x, n);
    if (residual <= run.tolerance) {
      run.reached = true;
      nlopt_force_stop(run.opt);
    }
  }
  return run.sigma * (run.g0.dot(d) + 0.5 * rd.dot(ud));
}

void NloptStep::StartRun(Run& run, const Eigen::VectorXd& y0) const {
  // Luksan's L-BFGS puts a variable within 1e-8 (absolute) of its bound onto it at once;
  // do it first, so that σ below sees the same active bounds.
  run.y0 = y0;
  for (Eigen::Index i = 0; i < y0.size(); ++i) {
    if (run.y0[i] < map_.lower[i] + kBoundSnap) run.y0[i] = map_.lower[i];
  }
  run.r0 = map_.e * run.y0;
  run.u0 = w_->Posed(run.r0);
  run.g0 = map_.e.transpose() * (run.u0 + *run.shift);
  // σ: the run's objective starts with a unit projected gradient (at a bound, only the
  // component pointing into the feasible side counts).
  double projected = 0.0;
  for (Eigen::Index i = 0; i < run.y0.size(); ++i) {
    const bool at_bound = run.y0[i] <= map_.lower[i];
    projected = std::max(projected, at_bound ? std::max(0.0, -run.g0[i]) : std::abs(run.g0[i]));
  }
  run.sigma = projected > 0.0 ? 1.0 / projected : 1.0;
}

nlopt_result NloptStep::RunOnce(Run& run, int evaluations_left, double seconds_left) const {
  const unsigned n = static_cast<unsigned>(map_.lower.size());
  const nlopt_algorithm algorithm =
      o_.nlopt.algorithm == NloptAlgorithm::kCcsaq ? NLOPT_LD_CCSAQ : NLOPT_LD_LBFGS;
  NloptHandle opt(nlopt_create(algorithm, n));
  if (!opt) return NLOPT_OUT_OF_MEMORY;
  run.opt = opt.get();
  nlopt_set_lower_bounds(run.opt, map_.lower.data());
  nlopt_set_min_objective(run.opt, Objective, &run);
  nlopt_set_maxeval(run.opt, evaluations_left);
  if (std::isfinite(seconds_left)) nlopt_set_maxtime(run.opt, std::max(seconds_left, 1e-3));
  nlopt_set_ftol_rel(run.opt, kRunFunctionTolerance);
  if (algorithm == NLOPT_LD_LBFGS) nlopt_set_vector_storage(run.opt, kLbfgsMemory);
  std::vector<double> x(run.y0.data(), run.y0.data() + n);
  double value = 0.0;
  return nlopt_optimize(run.opt, x.data(), &value);
}

ConvexStep NloptStep::Solve(const Eigen::VectorXd& shift, const Eigen::VectorXd& start,
                            double tolerance, double time_limit) {
  const solvers_internal::Deadline deadline(time_limit);
  ConvexStep out;
  Run run;
  run.step = this;
  run.shift = &shift;
  run.tolerance = tolerance;
  StartRun(run, EdgeValues(layout_, map_, start));
  run.best_y = run.y0;
  run.best_residual = law_.Residual(run.r0, run.u0, shift);
  run.reached = run.best_residual <= tolerance || map_.lower.empty();
  nlopt_result result = NLOPT_SUCCESS;
  while (!run.reached && run.evaluations < o_.nlopt.max_evaluations && !deadline.Passed()) {
    const double before = run.best_residual;
    result = RunOnce(run, o_.nlopt.max_evaluations - run.evaluations, deadline.SecondsLeft());
    if (run.reached || result == NLOPT_MAXEVAL_REACHED || result == NLOPT_MAXTIME_REACHED ||
        !(run.best_residual < before))
      break;
    StartRun(run, run.best_y);  // a run gains at most ~8 digits: restart from the best point
  }
  out.impulses = map_.e * run.best_y;
  out.iterations = run.evaluations;
  out.solved = run.reached;
  if (run.reached) result = NLOPT_SUCCESS;
  out.failure = result == NLOPT_MAXEVAL_REACHED || result == NLOPT_MAXTIME_REACHED ||
                        run.evaluations >= o_.nlopt.max_evaluations || deadline.Passed()
                    ? SolveStatus::kIterationLimit
                    : SolveStatus::kNumericalFailure;
  out.library_status = std::string("NLopt ") + nlopt_result_to_string(result);
  if (!run.reached && result != NLOPT_MAXEVAL_REACHED && result != NLOPT_MAXTIME_REACHED) {
    char detail[96];
    std::snprintf(detail, sizeof detail, ", a run without progress (convex residual %.3g)",
                  run.best_residual);
    out.library_status += detail;
  }
  return out;
}

}  // namespace

namespace {

template <class Problem>
double ImpulseScale(const Problem& p, const SolverGuess& guess) {
  const bool warm = guess.impulses.size() == p.NumUnknowns() && guess.impulses.allFinite();
  return ComputeResidual(p, warm ? guess.impulses : Eigen::VectorXd::Zero(p.NumUnknowns())).scale;
}

}  // namespace

SolveResult NloptSolver::DoSolve(const ContactProblem& p, const SolverOptions& options,
                                 const SolverGuess& guess) {
  NloptStep step(p, options, ImpulseScale(p, guess), std::make_unique<const BodyDelassus>(p));
  return SolveByDeSaxceFixedPoint(p, options, guess, Name(), step);
}

SolveResult NloptSolver::DoSolveDelassus(const DelassusProblem& p, const SolverOptions& options,
                                         const SolverGuess& guess) {
  const std::string not_convex = NotConvexOf(p);
  if (!not_convex.empty()) return Unsupported(p, Name(), not_convex);
  NloptStep step(p, options, ImpulseScale(p, guess), std::make_unique<const StoredDelassus>(p));
  return SolveByDeSaxceFixedPoint(p, options, guess, Name(), step);
}

}  // namespace unjam
