// One perturbation solved: the rate solve first (perturbation_rate.hpp), then the step's
// backend and its fallback on what it leaves, and the small-gap check of the answer.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include "perturbation_internal.hpp"
#include "unjam/problem/kinematic_admissibility.hpp"
#include "unjam/solvers/pattern_polish.hpp"

namespace unjam {

using namespace perturbation_internal;

namespace {
// The basis of a solution of the same base (another gap) for the contacts of `posed`, or
// empty if it has none. A contact it did not have (detected within the larger margin of
// a larger gap) enters as open: no impulse variable basic.
std::vector<std::uint8_t> BasisFor(const StaticProblem& posed, const StaticSolution& from) {
  if (from.basis.empty()) return {};
  const ContactProblem& p = posed.assembled.problem;
  std::vector<std::uint8_t> basis(p.NumContacts(), 0);
  for (int k = 0; k < p.NumContacts(); ++k) {
    const Contact& c = posed.contacts[posed.assembled.source_contact[k]];
    const int at = FindContact(from.contacts, c.i, c.j, c.image);
    if (at >= 0) basis[k] = from.basis[at];
  }
  return basis;
}

// Solves the posed step with solve.backend and measures the answer into r; where that
// leaves the step unresolved, solves it once more with the fallback backend (if any) and
// keeps that answer if it is resolved. The message keeps the first backend's account.
StaticSolution SolveAndMeasure(const PerturbationBase& base, const Scene& perturbed,
                               StaticProblem posed, const StaticSolveOptions& solve,
                               const PerturbationOptions& options, PerturbationResult& r) {
  const std::string fallback = PerturbationFallback(options, base.scene);
  std::optional<StaticProblem> spare;
  if (!fallback.empty()) spare = posed;
  StaticSolution s = SolveStatic(perturbed, std::move(posed), solve);
  Measure(base, options, solve, s, r);
  if (r.resolved || !spare) return s;
  StaticSolveOptions second = solve;
  second.backend = fallback;
  spare->guess.basis.clear();
  StaticSolution s2 = SolveStatic(perturbed, std::move(*spare), second);
  PerturbationResult r2 = r;
  Measure(base, options, second, s2, r2);
  const std::string first = r.solve.backend + ": " + r.solve.message;
  if (!r2.resolved) {
    r.solve.message += "; then " + r2.solve.backend + ": " + r2.solve.message;
    return s;
  }
  r2.solve.message = "after " + first + "; " + r2.solve.message;
  r = std::move(r2);
  return s2;
}

const RateBase& RateBaseOf(const PerturbationBase& base, const PerturbationOptions& options) {
  RateBaseSlot& slot = *base.rate;
  std::call_once(slot.once, [&] { slot.rate = PrepareRateBase(base, StepOptions(base, options)); });
  return slot.rate;
}

std::string PathAccount(const RatePathResult& path) {
  char text[200];
  std::snprintf(text, sizeof text, "rate path: %s after %d events, %d turns", ToString(path.end),
                path.events, path.turns);
  std::string account = text;
  if (path.free_mechanism_pieces > 0)
    account += ", " + std::to_string(path.free_mechanism_pieces) + " beside free mechanisms";
  if (path.pieces_oriented_by_t > 0)
    account += ", " + std::to_string(path.pieces_oriented_by_t) + " oriented by t";
  if (!path.message.empty()) account += ", " + path.message;
  return account;
}

std::string FormatResidual(double residual) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", residual);
  return text;
}

// The step's solution on the path's final contact states, measured into r. With
// `open_may_close`, the contacts open in the static state may close where the motion asks
// (the 10ξ check: a response that closes one there is judged by its misfit, as a step
// backend's is).
void MeasureOnPattern(const PerturbationBase& base, const RateBase& rb, const RateTarget& rt,
                      const RatePathResult& path, const PerturbationOptions& options,
                      const StaticSolveOptions& solve, const Scene& perturbed,
                      const StaticProblem& posed, const std::string& account, bool open_may_close,
                      PerturbationResult& r) {
  SolveResult step = StepOnPattern(rb, rt, path, posed, open_may_close);
  step.report.iterations = path.events;
  step.report.message =
      account + "; the step on its pattern: residual " + FormatResidual(step.report.residual);
  StaticSolution s = SolutionOf(perturbed, posed, step, options.dt);
  Measure(base, options, solve, s, r);
}

// The small-gap check of a rate answer: the step at 10ξ solved on the same contact states.
// Where that is no solution of the step (its residual above the tolerance), the response
// at 10ξ is not 10 times this one: nonlinear.
void CheckLinearityOnPattern(const PerturbationBase& base, const PerturbationTarget& target,
                             const RateBase& rb, const RateTarget& rt, const RatePathResult& path,
                             const PerturbationOptions& options, PerturbationResult& r) {
  PerturbationOptions scaled = options;
  scaled.gap *= kLinearityGapFactor;
  scaled.max_inertia_ratio *= kLinearityGapFactor;  // a linear response's inertia grows with ξ
  const StaticSolveOptions solve = StepOptions(base, scaled);
  const Scene perturbed = PerturbedScene(base, target, scaled);
  const StaticProblem posed = PoseStaticProblem(perturbed, solve);
  PerturbationResult check;
  check.target = target;
  SetOriginAndReference(base, target, check);
  MeasureOnPattern(base, rb, rt, path, scaled, solve, perturbed, posed, "", true, check);
  r.solve.message += "; 10 xi check: residual " + FormatResidual(check.solve.residual);
  if (!check.resolved) {
    r.linear = false;
    r.status = PerturbationStatus::kNonlinear;
    r.solve.message += ", not a solution of the step at 10 xi";
    return;
  }
  JudgeLinearity(base, check, r);
}

// The perturbation solved as the rigid limit of stiff contacts (perturbation_rate.hpp):
// its answer, or none where the path gives no definite one (`account` then says why, and
// the step is solved by a backend).
std::optional<PerturbationResult> PerturbByRate(const PerturbationBase& base,
                                                const PerturbationTarget& target,
                                                const PerturbationOptions& options,
                                                const StaticSolveOptions& solve,
                                                const Scene& perturbed, const StaticProblem& posed,
                                                PerturbationResult r, Clock::time_point start,
                                                std::string& account) {
  if (base.rate == nullptr) return std::nullopt;
  const RateBase& rb = RateBaseOf(base, options);
  const RateTarget rt = PoseRateTarget(rb, target, options);
  if (!rt.refused.empty()) {
    account = "rate path: " + rt.refused;
    return std::nullopt;
  }
  if (!rt.problem.released_rows.empty()) {
    // Released forces (the held contact's friction): is there still a static network?
    const RateStaticLp lp = SolveRateStaticLp(rt.problem);
    if (lp.decided && !lp.feasible) {
      PerturbationResult d = std::move(r);
      d.solve.status = SolveStatus::kConverged;
      d.solve.iterations = lp.iterations;
      d.resolved = true;
      d.status = PerturbationStatus::kDynamic;
      return DecidedWithoutSolving(
          base, "static LP",
          "no static network holds the packing with the perturbation's forces released (" +
              lp.message + "): dynamic, not solved",
          std::move(d), start);
    }
  }
  const RatePathResult path = FollowRatePath(rt.problem);
  account = PathAccount(path);
  if (path.end != RatePathEnd::kCollapse) return std::nullopt;
  MeasureOnPattern(base, rb, rt, path, options, solve, perturbed, posed, account, false, r);
  if (!r.resolved) {  // the path's pattern is no solution of the step: the step solver decides
    account += "; its pattern is no solution of the step (residual " +
               FormatResidual(r.solve.residual) + ")";
    return std::nullopt;
  }
  if (r.status == PerturbationStatus::kOk && options.check_linearity)
    CheckLinearityOnPattern(base, target, rb, rt, path, options, r);
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

// The whole measurement at one gap; `continued`: the answer at another gap, whose basis
// the solve tries first (check_by_continuation; the warm start stays the static forces,
// from which newton resolves a frictionless response further than from that answer);
// `answer`: this one's solution.
PerturbationResult PerturbOnce(const PerturbationBase& base, const PerturbationTarget& target,
                               const PerturbationOptions& options,
                               const StaticSolution* continued = nullptr,
                               StaticSolution* answer = nullptr) {
  const auto start = Clock::now();
  CheckTarget(base, target);
  PerturbationResult r;
  r.target = target;
  SetOriginAndReference(base, target, r);

  const StaticSolveOptions solve = StepOptions(base, options);
  const Scene perturbed = PerturbedScene(base, target, options);
  // Blocked perturbations have no response to measure: say so instead of reporting what a
  // solver makes of an infeasible step (runaway forces, or penetrations spread below its
  // tolerance). An opening under a pressure bath is never blocked: a uniform expansion
  // of the cell opens every contact (u_n = λ l·n > 0), so it needs no check.
  const bool always_admissible = target.kind == PerturbationTarget::Kind::kContactOpening &&
                                 options.cell == CellCondition::kFixedPressure &&
                                 base.scene.effects.pressure_bath.has_value();
  StaticProblem posed = PoseStaticProblem(perturbed, solve);
  if (continued != nullptr) posed.guess.basis = BasisFor(posed, *continued);
  if (!posed.assembled.violated_immovable.empty()) {
    // A particle shifted into a fixed one: no impulse can keep that contact closed.
    const Contact& c = posed.contacts[posed.assembled.violated_immovable.front()];
    return Blocked(base, "known motion", DescribeImmovableViolation(c), std::move(r), start);
  }
  if (!always_admissible) {
    const KinematicAdmissibility kinematics = CheckKinematicAdmissibility(posed.assembled.problem);
    if (kinematics.decided && !kinematics.admissible)
      return Blocked(base, "kinematic LP", kinematics.message, std::move(r), start);
  }
  std::string rate_account;
  if (PerturbationBackend(options, base.scene) == "rate" && continued == nullptr) {
    if (auto answered =
            PerturbByRate(base, target, options, solve, perturbed, posed, r, start, rate_account)) {
      return std::move(*answered);
    }
  }
  StaticSolution s = SolveAndMeasure(base, perturbed, std::move(posed), solve, options, r);
  if (!rate_account.empty())
    r.solve.message = rate_account + "; then " + r.solve.backend + ": " + r.solve.message;
  if (answer != nullptr) *answer = std::move(s);
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}
}  // namespace

PerturbationResult Perturb(const PerturbationBase& base, const PerturbationTarget& target,
                           const PerturbationOptions& options) {
  const auto start = Clock::now();
  StaticSolution answer;
  PerturbationResult r = PerturbOnce(base, target, options, nullptr, &answer);
  // A rate answer had its own check at 10ξ, on its contact states (CheckLinearityOnPattern).
  if (!options.check_linearity || !r.ok() || r.solve.backend == "rate") return r;
  PerturbationOptions scaled = options;
  scaled.gap *= kLinearityGapFactor;
  // A linear response's inertia grows with the gap, so at 10ξ it is judged against a
  // threshold 10 times as high: the same regime, not a stricter one.
  scaled.max_inertia_ratio *= kLinearityGapFactor;
  // An answer of the fallback is checked by the fallback: the first backend left the step
  // at ξ unresolved, and would most likely fail again at 10ξ.
  const std::string fallback = PerturbationFallback(options, base.scene);
  if (!fallback.empty() && r.solve.backend == fallback) {
    scaled.backend = r.solve.backend;
    scaled.fallback = "none";
  }
  const PerturbationResult check =
      PerturbOnce(base, target, scaled, options.check_by_continuation ? &answer : nullptr);
  if (!check.resolved) {  // no verdict: the result cannot be certified
    r.resolved = false;
    r.status = PerturbationStatus::kNotConverged;
    r.solve.message += (r.solve.message.empty() ? "" : "; ") +
                       std::string("the 10 xi check did not converge: ") + check.solve.message;
  } else {
    JudgeLinearity(base, check, r);
    r.solve.message +=
        (r.solve.message.empty() ? "" : "; ") + std::string("10 xi check: ") + check.solve.message;
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

}  // namespace unjam
