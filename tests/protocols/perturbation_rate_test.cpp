// The default perturbation solve (backend "rate": the quasi-rigid loading path in the
// self-stress space, then the step solved exactly on its contact states), against Lemke's
// exact solve of the whole step and the LP intervals of the admissible forces.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "protocols/perturbation_rate.hpp"
#include "unjam/indeterminacy/equilibrium_system.hpp"
#include "unjam/indeterminacy/force_bounds.hpp"
#include "unjam/indeterminacy/shift_bounds.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/perturbation.hpp"
#include "unjam/solvers/rate_path.hpp"

namespace unjam {
namespace {

Scene Bundled(const std::string& name) {
  return ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/" + name + ".unjam");
}

int ContactIndex(const EquilibriumSystem& system, const PerturbationTarget& t) {
  for (int c = 0; c < static_cast<int>(system.contacts.size()); ++c) {
    const Contact& k = system.contacts[static_cast<std::size_t>(c)];
    if (k.i == t.i && k.j == t.j && k.image == t.image) return c;
  }
  return -1;
}

// F_crit of an opening lies in its contact's interval over the admissible static networks
// [min, max without friction] (indeterminacy/force_bounds.hpp): a quasi-static response
// ends on a static network with the contact's force released.
void ExpectInsideTheContactsLpInterval(const EquilibriumSystem& system,
                                       const PerturbationResult& r) {
  const int k = ContactIndex(system, r.target);
  ASSERT_GE(k, 0);
  const BoundsReport b = ComputeForceBounds(system, {k}, {});
  ASSERT_TRUE(b.bounds[0].min.ok() && b.bounds[0].max_without_friction.ok());
  EXPECT_GE(r.f_crit, b.bounds[0].min.value - 1e-6) << r.target.i << "-" << r.target.j;
  EXPECT_LE(r.f_crit, b.bounds[0].max_without_friction.value + 1e-6)
      << r.target.i << "-" << r.target.j;
}

// Lemke's exact solve of the whole step, the cross-check of the rate solve's answers.
PerturbationOptions WholeStepLemke(PerturbationOptions o) {
  o.backend = "lemke";
  o.check_linearity = false;
  return o;
}

// On the default packing (μ = 0.5) every sampled opening ends with a definite status. Where
// the static LP finds no network that holds the packing with the contact's friction
// released, the opening is dynamic without a solve, and Lemke's exact solve of the step
// agrees. Where the rate solve answers, its answer is an exact solution of the step (the
// residual at the tolerance) inside the LP interval; where Lemke also finds a quasi-static
// one, the two agree unless the step has several solutions (then each is exact).
TEST(RatePerturbation, DefaultPackingOpeningsAreDecidedAndAgreeWithLemke) {
  const Scene scene = Bundled("pressure-n500-mu0.5");
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const EquilibriumSystem system = BuildEquilibriumSystem(scene);
  const PerturbationOptions lemke = WholeStepLemke(o);
  int by_lp = 0, by_rate = 0;
  for (const PerturbationTarget& t : SampleTargets(ContactTargets(base), 10, 4)) {
    const PerturbationResult r = Perturb(base, t, o);
    ASSERT_NE(r.status, PerturbationStatus::kNotConverged)
        << t.i << "-" << t.j << ": " << r.solve.message;
    if (r.solve.backend == "static LP") {
      ++by_lp;
      EXPECT_EQ(r.status, PerturbationStatus::kDynamic);
      EXPECT_TRUE(std::isnan(r.f_crit));
      EXPECT_EQ(Perturb(base, t, lemke).status, PerturbationStatus::kDynamic) << t.i << "-" << t.j;
      continue;
    }
    if (r.solve.backend != "rate") continue;
    ++by_rate;
    EXPECT_TRUE(r.resolved);
    EXPECT_LE(r.solve.residual, 4.1e-12) << r.solve.message;
    if (r.ok()) ExpectInsideTheContactsLpInterval(system, r);
  }
  EXPECT_GT(by_lp, 0);
  EXPECT_GT(by_rate, 0);
}

// The self-stresses and static forces of the rate solve, as the perturbation step poses them.
RateBase RateBaseFor(const PerturbationBase& base, const PerturbationOptions& o) {
  StaticSolveOptions step;
  step.dt = o.dt;
  step.closed_gap_tolerance = o.closed_gap_tolerance;
  step.margin = std::max(1e-6, 1000.0 * o.gap);  // the perturbation step's detection margin
  return PrepareRateBase(base, step);
}

// The static LP's cutting planes (a relaxation over the rows nearest to binding, grown by
// the rows its point violates) decide every opening of the default packing as the LP over
// every row does: the fast path against the whole LP, on all 643 openings.
TEST(RatePerturbation, StaticLpCuttingPlanesAgreeWithTheWholeLp) {
  const Scene scene = Bundled("pressure-n500-mu0.5");
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const RateBase rb = RateBaseFor(base, o);
  int infeasible = 0, openings = 0;
  for (const PerturbationTarget& t : ContactTargets(base)) {
    const RateTarget rt = PoseRateTarget(rb, t, o);
    ASSERT_TRUE(rt.refused.empty()) << rt.refused;
    const RateStaticLp fast = SolveRateStaticLp(rt.problem);
    const RateStaticLp whole = SolveRateStaticLp(rt.problem, {.every_row = true});
    ASSERT_TRUE(fast.decided && whole.decided) << fast.message << " / " << whole.message;
    EXPECT_EQ(fast.feasible, whole.feasible)
        << t.i << "-" << t.j << ": " << fast.message << " / " << whole.message;
    infeasible += fast.feasible ? 0 : 1;
    ++openings;
  }
  EXPECT_EQ(openings, 643);
  EXPECT_EQ(infeasible, 367);  // the openings Lemke's full solve of the step calls dynamic
}

// The path's ratio test reads only the contacts whose margin can reach a bound within the
// step (solvers/reach_heap.hpp); reading every contact at every event gives the same path,
// event for event: brute force against the fast path, on low-friction openings whose paths
// take hundreds of events.
TEST(RatePerturbation, PathsReadingOnlyContactsNearABoundAreThePathsReadingEveryContact) {
  const Scene scene = Bundled("pressure-n500-mu0.1");
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const RateBase rb = RateBaseFor(base, o);
  int long_paths = 0;
  for (const PerturbationTarget& t : SampleTargets(ContactTargets(base), 6, 1)) {
    const RateTarget rt = PoseRateTarget(rb, t, o);
    ASSERT_TRUE(rt.refused.empty()) << rt.refused;
    const RatePathResult fast = FollowRatePath(rt.problem);
    const RatePathResult every = FollowRatePath(rt.problem, {.read_every_contact = true});
    EXPECT_EQ(fast.end, every.end) << t.i << "-" << t.j;
    EXPECT_EQ(fast.events, every.events) << t.i << "-" << t.j;
    EXPECT_EQ(fast.states, every.states) << t.i << "-" << t.j;
    EXPECT_EQ(fast.t, every.t) << t.i << "-" << t.j;
    EXPECT_EQ((fast.alpha - every.alpha).lpNorm<Eigen::Infinity>(), 0.0) << t.i << "-" << t.j;
    long_paths += fast.events >= 300 ? 1 : 0;
  }
  EXPECT_GE(long_paths, 3);
}

// Every top and bottom shift of the small pile ends with a definite status; the top shifts
// the rate solve answers quasi-statically lie in the shift's interval over the admissible
// networks (indeterminacy/shift_bounds.hpp).
TEST(RatePerturbation, SmallPileShiftsAreDecided) {
  const Scene scene = Bundled("gravity-n100-mu0.5");
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const EquilibriumSystem system = BuildEquilibriumSystem(scene);
  std::vector<PerturbationTarget> targets = TopTargets(base);
  const std::vector<PerturbationTarget> bottom = BottomTargets(base);
  targets.insert(targets.end(), bottom.begin(), bottom.end());
  int by_rate = 0;
  for (const PerturbationTarget& t : targets) {
    const PerturbationResult r = Perturb(base, t, o);
    ASSERT_NE(r.status, PerturbationStatus::kNotConverged) << t.i << ": " << r.solve.message;
    if (r.solve.backend != "rate" || !r.ok() || t.direction.y() > 0.0) continue;
    ++by_rate;
    const ShiftBoundsReport lp = ComputeShiftBounds(system, {{t.i, t.direction}}, {});
    ASSERT_TRUE(lp.feasible && lp.bounds[0].min.ok() && lp.bounds[0].max.ok()) << lp.message;
    EXPECT_GE(r.f_crit, lp.bounds[0].min.value - 1e-6) << t.i;
    EXPECT_LE(r.f_crit, lp.bounds[0].max.value + 1e-6) << t.i;
  }
  EXPECT_GT(by_rate, 0);
}

// At μ = 0.1 the loading paths are long (about 1 000 events, dozens of turns): they still
// collapse, and the step on the collapse's pattern is solved exactly. Lemke's solve of the
// whole step finds a quasi-static answer too; the step has a family of solutions (forces
// that differ by self-stresses), so both must be exact, not equal.
TEST(RatePerturbation, LongPathsAtLowFrictionEndInAnExactAnswer) {
  const Scene scene = Bundled("pressure-n500-mu0.1");
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const EquilibriumSystem system = BuildEquilibriumSystem(scene);
  const PerturbationOptions lemke = WholeStepLemke(o);
  const std::vector<PerturbationTarget> sample = SampleTargets(ContactTargets(base), 10, 1);
  for (int a = 0; a < 2; ++a) {
    const PerturbationTarget& t = sample[static_cast<std::size_t>(a)];
    const PerturbationResult r = Perturb(base, t, o);
    EXPECT_EQ(r.solve.backend, "rate") << r.solve.message;
    EXPECT_EQ(r.status, PerturbationStatus::kOk) << r.solve.message;
    EXPECT_GT(r.solve.iterations, 400) << "path events";
    EXPECT_LE(r.solve.residual, 1e-14) << r.solve.message;
    ExpectInsideTheContactsLpInterval(system, r);
    if (a > 0) continue;  // one Lemke solve (10-20 s) is enough
    const PerturbationResult exact = Perturb(base, t, lemke);
    EXPECT_EQ(exact.status, PerturbationStatus::kOk) << exact.solve.message;
    EXPECT_LE(exact.solve.residual, 1e-14) << exact.solve.message;
    EXPECT_NEAR(r.f_crit, exact.f_crit, 1e-3 * exact.f_crit);
  }
}

// A top shift of the 1600-disk pile at mu = 0.1, down: the rate solve's answer is exact,
// linear, lemke's (F_crit from lemke's exact solve of the whole step, 18-25 minutes each:
// the pile ensemble's records in git at c2d67e6^) and inside the shift's LP interval.
void ExpectPileShiftIsLemkes(int particle, double lemke_f_crit, double tolerance = 1e-9,
                             PerturbationResult* answer = nullptr) {
  const Scene scene = Bundled("gravity-n1600-mu0.1");
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const PerturbationTarget t = ParticleShift(base, particle, Vec2(0.0, -1.0));
  const PerturbationResult r = Perturb(base, t, o);
  EXPECT_EQ(r.solve.backend, "rate") << r.solve.message;
  EXPECT_EQ(r.status, PerturbationStatus::kOk) << r.solve.message;
  EXPECT_LE(r.solve.residual, 1e-14) << r.solve.message;
  EXPECT_LE(r.linearity_misfit, 1e-3);
  EXPECT_NEAR(r.f_crit, lemke_f_crit, tolerance);
  if (answer != nullptr) *answer = r;
  const ShiftBoundsReport lp =
      ComputeShiftBounds(BuildEquilibriumSystem(scene), {{t.i, t.direction}}, {});
  ASSERT_TRUE(lp.feasible && lp.bounds[0].min.ok() && lp.bounds[0].max.ok()) << lp.message;
  EXPECT_GE(r.f_crit, lp.bounds[0].min.value - 1e-6);
  EXPECT_LE(r.f_crit, lp.bounds[0].max.value + 1e-6);
}

// A top shift of the 1600-disk pile: the path collapses after 205 events and the step on
// its pattern is exact at once (residual 2e-15). Corrections that changed every contact
// breaking its law by rounding left that answer and ended near 2e-10, then newton stalled
// (not-converged after 45 s). At 10 ξ the response closes a contact open in the static
// state (a gap of a few ξ); solved with it closed, the response is 10 times this one.
TEST(RatePerturbation, PileShiftIsSolvedExactlyOnThePathsPattern) {
  ExpectPileShiftIsLemkes(1561, 4.2539918282);
}

// This path reaches pieces on which the forces hold while t grows (a collapse mechanism)
// and goes on past them (one of its slips runs backwards and stops) to t ~ 1e15: the forces
// must be carried exactly there, and the orientation after a contact sticks on such a piece
// taken from t (no force moves along it).
TEST(RatePerturbation, PileShiftPastCollapsePiecesIsSolvedExactly) {
  ExpectPileShiftIsLemkes(709, 4.7165926208);
}

// Near this path's end a piece loses rank: a second mechanism forms beside the one it was
// growing, and the kernel holds a combination that moves no force while t grows (a collapse
// piece). Taken as such, the path ends on lemke's answer; refused, it ended `singular` and
// newton stalled near 1e-11 (not-converged).
TEST(RatePerturbation, PileShiftWhoseKernelHoldsTwoMechanismsEndsOnTheCollapse) {
  ExpectPileShiftIsLemkes(566, 18.6549141381);
}

// On this path a grain comes to slide on every contact: its spin is a free mechanism (the
// forces and t do not move along it), a second direction of the piece's kernel, and the
// path goes on beside it. Further on, a contact starts sliding whose slip does not move on
// the next piece (the mechanism moved it), and that piece is oriented by t. The path then
// collapses on lemke's answer (F_crit to 1e-7: the two members' O(ξ) inertial parts
// differ). Without either rule the path ended `singular` and newton stalled.
TEST(RatePerturbation, PileShiftPastAGrainSpinningFreelyEndsOnTheCollapse) {
  PerturbationResult r;
  ExpectPileShiftIsLemkes(713, 24.3764648730, 1e-6, &r);
  EXPECT_NE(r.solve.message.find("beside free mechanisms"), std::string::npos) << r.solve.message;
  EXPECT_NE(r.solve.message.find("oriented by t"), std::string::npos) << r.solve.message;
}

}  // namespace
}  // namespace unjam
