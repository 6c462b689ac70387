// Perturbations with known answers: a disk in a frictionless V-groove (the opened contact
// carries its static force, the disk slides along the other support), a column of disks
// (lifting a disk lifts the one above it; in a channel one diameter wide, k of them), and
// the frictionless bundled packing (unique forces: every critical force equals the contact
// force).
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

#include <Eigen/LU>
#include <gtest/gtest.h>

#include "test_scenes.hpp"
#include "unjam/indeterminacy/shift_bounds.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/perturbation.hpp"
#include "unjam/protocols/response_ensemble.hpp"
#include "unjam/protocols/static_solve.hpp"

namespace unjam {
namespace {

using testing::Disk;

// Solves the static forces of `scene` and stores them, as a saved static packing has.
Scene WithStaticForces(Scene scene) {
  StaticSolveOptions o;
  o.solver.tolerance = 1e-14;
  const StaticSolution s = SolveStatic(scene, o);
  EXPECT_TRUE(s.report.converged()) << s.report.residual;
  scene.forces = ToContactForces(s);
  return scene;
}

// The frictionless V-groove (test_scenes.hpp) with its static forces.
Scene VGroove(double a) { return WithStaticForces(testing::VGroove(a, 0.0)); }

PerturbationTarget Opening(int i, int j) {
  PerturbationTarget t;
  t.kind = PerturbationTarget::Kind::kContactOpening;
  t.i = i;
  t.j = j;
  return t;
}

// The opening of contact i–j among the base's force-carrying contacts (i = −1 if it is not one).
PerturbationTarget OpeningOf(const PerturbationBase& base, int i, int j) {
  for (const PerturbationTarget& t : ContactTargets(base)) {
    if (t.i == i && t.j == j) return t;
  }
  return Opening(-1, -1);
}

PerturbationTarget Shift(int particle, Vec2 direction) {
  PerturbationTarget t;
  t.kind = PerturbationTarget::Kind::kParticleShift;
  t.i = particle;
  t.direction = direction;
  return t;
}

TEST(Perturbation, VGrooveOpeningNeedsTheStaticForceAndSlidesAlongTheOtherSupport) {
  const double a = 1.2;
  const Scene scene = VGroove(a);
  const double h = std::sqrt(4.0 - a * a);
  const double weight = std::numbers::pi;
  const double static_force = weight / (2.0 * h / 2.0);  // each support: m g / (2 cos θ)
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const PerturbationResult r = Perturb(base, Opening(0, 2), o);
  ASSERT_EQ(r.status, PerturbationStatus::kOk) << r.solve.residual;
  EXPECT_NEAR(r.f_reference, static_force, 1e-12);
  EXPECT_NEAR(r.f_crit, static_force, 1e-7 * static_force);
  // Kinematics: the opened contact moves apart by ξ, the other stays closed.
  const Vec2 n_left = Vec2(a, h) / 2.0, n_right = Vec2(-a, h) / 2.0;
  Eigen::Matrix2d rows;
  rows << n_left.x(), n_left.y(), n_right.x(), n_right.y();
  const Vec2 expected = rows.inverse() * Vec2(o.gap, 0.0);
  EXPECT_LT((r.displacement[2] - expected).norm(), 1e-3 * o.gap);
  EXPECT_EQ(r.displacement[0], Vec2::Zero());
  // The response scales with ξ; the critical force does not, nor does it depend on Δt.
  PerturbationOptions ten = o;
  ten.gap = 1e-8;
  const PerturbationResult r10 = Perturb(base, Opening(0, 2), ten);
  EXPECT_LT((r10.displacement[2] - 10.0 * r.displacement[2]).norm(), 1e-3 * ten.gap);
  EXPECT_NEAR(r10.f_crit, r.f_crit, 1e-7 * static_force);
  // With Δt = 0.1 the inertia ratio is 100 times larger; at 10ξ (the default small-gap
  // check) it crosses the 1e-6 of a quasi-static step, and the check must judge it against
  // 10 times that threshold, as a linear response's inertia grows with ξ.
  PerturbationOptions short_step = o;
  short_step.dt = 0.1;
  const PerturbationResult rdt = Perturb(base, Opening(0, 2), short_step);
  ASSERT_EQ(rdt.status, PerturbationStatus::kOk)
      << rdt.inertia_ratio << " " << rdt.linearity_misfit;
  EXPECT_LT(rdt.linearity_misfit, 1e-3);
  EXPECT_NEAR(rdt.f_crit, r.f_crit, 1e-6 * static_force);
  EXPECT_LT((rdt.displacement[2] - r.displacement[2]).norm(), 1e-3 * o.gap);
}

TEST(Perturbation, ContactFrameAndPenetrationDepthOfTheVGroove) {
  const Scene scene = VGroove(1.2);
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const PerturbationResult r = Perturb(base, Opening(0, 2), o);
  const Vec2 contact_point = scene.particles[0].position + r.axis;  // R = 1 along n
  EXPECT_LT((r.origin - contact_point).norm(), 1e-12);
  // One moving disk: δ is the distance of its centre from the contact along the normal.
  EXPECT_NEAR(r.penetration_depth, std::abs((scene.particles[2].position - r.origin).dot(r.axis)),
              1e-12);
}

// Fixed disk 0, disk 1 on it, a smaller disk 2 on top; frictionless, exactly vertical.
Scene Column() {
  Scene s;
  s.cell.size = Vec2(20.0, 20.0);
  s.cell.periodicity = Periodicity::kX;
  s.effects.gravity = Vec2(0.0, -1.0);
  s.particles = {Disk(5.0, 1.0, 1.0, true), Disk(5.0, 3.0, 1.0), Disk(5.0, 4.5, 0.5)};
  return WithStaticForces(s);
}

TEST(Perturbation, LiftingADiskOfAColumnLiftsTheDiskAbove) {
  const Scene scene = Column();
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const std::vector<PerturbationTarget> bottom = BottomTargets(base);
  ASSERT_EQ(bottom.size(), 1u);
  EXPECT_EQ(bottom[0].i, 1);
  EXPECT_EQ(bottom[0].direction, Vec2(0.0, 1.0));
  const PerturbationResult r = Perturb(base, bottom[0], o);
  ASSERT_EQ(r.status, PerturbationStatus::kOk) << r.solve.residual;
  const double m1 = scene.particles[1].Mass(), m2 = scene.particles[2].Mass();
  // It carries the disk above, and accelerates it by ξ/Δt within the step (the inertial
  // part, ξ/Δt² relative to g: 1e-9 here).
  EXPECT_NEAR(r.f_crit, m2 * (1.0 + o.gap / (o.dt * o.dt)), 1e-12 * m2);
  EXPECT_NEAR(r.f_reference, m1 + m2, 1e-12);  // F_y: the support from below
  EXPECT_LT((r.displacement[2] - Vec2(0.0, o.gap)).norm(), 1e-3 * o.gap);
}

// A step the first backend leaves unresolved (newton allowed no Newton step, on an opening
// of the μ = 0.5 packing, where the pattern of its NSGS warm-up is too far off for the
// polish) is solved again by the fallback, whose answer is the one kept, with the first
// backend's account in the message. (On the frictionless packing the polish alone
// resolves such a step.)
TEST(Perturbation, TheFallbackSolvesWhatTheFirstBackendLeaves) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  PerturbationOptions o;
  o.backend = "newton";
  o.solver.newton.max_iterations = 0;
  o.fallback = "none";
  o.check_linearity = false;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const PerturbationTarget opening = SampleTargets(ContactTargets(base), 1, 3).at(0);
  const PerturbationResult alone = Perturb(base, opening, o);
  ASSERT_FALSE(alone.resolved)
      << "newton without a Newton step resolved it: the test needs a failing first backend";
  o.fallback = "lemke";
  const PerturbationResult r = Perturb(base, opening, o);
  ASSERT_TRUE(r.resolved) << r.solve.message;
  EXPECT_EQ(r.solve.backend, "lemke");
  EXPECT_EQ(r.solve.message.rfind("after newton: ", 0), 0u) << r.solve.message;
  EXPECT_LE(r.solve.residual, 1e-14);
}

TEST(Perturbation, TheAutoFallbackIsIpoptAfterLemkeAndLemkeAfterNewton) {
  const Scene frictional = testing::VGroove(1.2, 0.5), frictionless = testing::VGroove(1.2, 0.0);
  PerturbationOptions o;  // backend and fallback "auto"
  EXPECT_EQ(PerturbationFallback(o, frictional), "ipopt");
  EXPECT_EQ(PerturbationFallback(o, frictionless), "lemke");
  o.backend = "lemke";  // a named backend is not second-guessed
  EXPECT_EQ(PerturbationFallback(o, frictional), "");
  o.fallback = "newton";
  EXPECT_EQ(PerturbationFallback(o, frictional), "newton");
  o.fallback = "lemke";  // the same backend again is no fallback
  EXPECT_EQ(PerturbationFallback(o, frictional), "");
  o.fallback = "none";
  o.backend = "auto";
  EXPECT_EQ(PerturbationFallback(o, frictional), "");
  o.fallback = "simplex";
  EXPECT_THROW(Validate(o), std::invalid_argument);
}

TEST(Perturbation, AutoSolvesByRateAndGivesUndecidedLargeFrictionalStepsToNewton) {
  // The rate solve first at every size; where it gives no definite answer, the whole step:
  // Lemke's paths on the bundled N = 3000 packing (3 854 force-carrying contacts) run out
  // of their budget after 12 minutes, where newton answers in half a minute; the N = 500
  // one stays lemke's.
  const std::string dir = std::string(UNJAM_SOURCE_DIR) + "/problems/";
  const Scene small = ReadPacking(dir + "pressure-n500-mu0.5.unjam");
  const Scene large = ReadPacking(dir + "pressure-n3000-mu0.5.unjam");
  Scene large_frictionless = large;
  large_frictionless.effects.friction = 0.0;
  PerturbationOptions o;
  EXPECT_EQ(PerturbationBackend(o, small), "rate");
  EXPECT_EQ(PerturbationBackend(o, large), "rate");
  EXPECT_EQ(StepBackend(o, small), "lemke");
  EXPECT_EQ(PerturbationFallback(o, small), "ipopt");
  EXPECT_EQ(StepBackend(o, large), "newton");
  EXPECT_EQ(PerturbationFallback(o, large), "") << "lemke would take minutes to fail after newton";
  EXPECT_TRUE(AutoLeavesLemkeForSize(o, large))
      << "the case in which perturb names lemke as the remedy";
  EXPECT_FALSE(AutoLeavesLemkeForSize(o, small));
  EXPECT_FALSE(AutoLeavesLemkeForSize(o, large_frictionless))
      << "newton is auto's own choice without friction";
  EXPECT_EQ(StepBackend(o, large_frictionless), "newton");
  EXPECT_EQ(PerturbationFallback(o, large_frictionless), "lemke")
      << "a frictionless step keeps lemke after newton";
  o.solver.lemke.pivots_per_row = 50;  // an option only lemke reads names the backend
  EXPECT_EQ(PerturbationBackend(o, large), "lemke");
  EXPECT_EQ(StepBackend(o, large), "lemke");
  EXPECT_FALSE(AutoLeavesLemkeForSize(o, large));
  EXPECT_EQ(PerturbationFallback(o, large), "ipopt");
  o.solver.lemke.pivots_per_row = 0;
  o.cell = CellCondition::kFixedVolume;  // newton at fixed volume, whatever the size
  EXPECT_EQ(PerturbationBackend(o, small), "rate");
  EXPECT_EQ(StepBackend(o, small), "newton");
  EXPECT_EQ(PerturbationFallback(o, small), "");
  EXPECT_FALSE(AutoLeavesLemkeForSize(o, large))
      << "at fixed volume lemke ends on the unloaded solution";
  o.cell = CellCondition::kFixedPressure;
  o.backend = "newton";  // a backend the user names is not second-guessed
  EXPECT_EQ(PerturbationBackend(o, small), "newton");
  EXPECT_EQ(StepBackend(o, small), "newton");
  EXPECT_FALSE(AutoLeavesLemkeForSize(o, large));
}

TEST(Perturbation, PushingIntoARigidColumnIsReportedNotMeasured) {
  const Scene scene = Column();
  PerturbationOptions o;
  o.solver.SetIterationLimit(2000);
  const PerturbationBase base = PreparePerturbations(scene, o);
  const std::vector<PerturbationTarget> top = TopTargets(base);
  ASSERT_EQ(top.size(), 1u);
  EXPECT_EQ(top[0].i, 2);
  const PerturbationResult r = Perturb(base, top[0], o);
  // The disks below are rigid and the floor fixed: no motion moves the top disk down. The
  // kinematic LP says so before any solver runs (Newton used to find forces ~200× the
  // static ones with the disks overlapping by ξ/2), and no force is reported.
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.status, PerturbationStatus::kBlocked) << r.f_crit << " " << r.solve.residual;
  EXPECT_TRUE(std::isnan(r.f_crit));
  // Lifting the middle disk is not blocked (the column test above measures it).
  PerturbationTarget lift = top[0];
  lift.i = 1;
  lift.direction = Vec2(0.0, 1.0);
  EXPECT_NE(Perturb(base, lift, o).status, PerturbationStatus::kBlocked);
}

// The top disk of the column lifted by ξ leaves its only contact: it needs no force (a
// rattler, by the bottom shift's definition). The rate solve opens that contact at the
// first event, with exactly no force. From the static forces newton crawls along the
// column's self-stress (the contact keeps the disk's weight to within ξ) and leaves the
// step unresolved; lemke solves it exactly.
TEST(Perturbation, LiftingALoneDiskNeedsNoForce) {
  const Scene scene = Column();
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const PerturbationTarget lift = ParticleShift(base, 2, Vec2(0.0, 1.0));
  const PerturbationResult r = Perturb(base, lift, o);
  ASSERT_EQ(r.status, PerturbationStatus::kOk) << r.solve.message;
  EXPECT_EQ(r.f_crit, 0.0);
  EXPECT_FALSE(std::signbit(r.f_crit));
  EXPECT_EQ(r.solve.backend, "rate") << r.solve.message;
  EXPECT_LT(r.displacement[1].norm(), 1e-3 * o.gap);  // the disk below stays
  const EnsembleOptions ensemble;
  EXPECT_TRUE(Reduce(base, r, MakeLayout(base, ensemble, o.gap), ensemble).rattler);
  o.backend = "lemke";
  const PerturbationResult by_lemke = Perturb(base, lift, o);
  EXPECT_EQ(by_lemke.status, PerturbationStatus::kOk);
  EXPECT_EQ(by_lemke.f_crit, 0.0);
  o.backend = "newton";
  o.fallback = "none";
  EXPECT_EQ(Perturb(base, lift, o).status, PerturbationStatus::kNotConverged);
}

// k equal disks (radius 1/2, mass π/4) stacked on a floor in a frictionless channel one
// diameter wide: each touches both side walls. Lifting the lowest disk by ξ lifts the k−1
// above it, so F_crit is their weight plus the inertial part of moving them by ξ in one
// step, (k−1) m g (1 + ξ/(g Δt²)); for k = 1 it needs no force. Pushing the top disk down is
// blocked: by the kinematic LP above the floor, by the known motions alone for k = 1 (the
// floor cannot give way). Sliding along the side walls is free.
TEST(Perturbation, AColumnInAChannelOneDiameterWide) {
  for (const int k : {1, 3, 5}) {
    Scene scene;
    scene.cell.size = Vec2(10.0, k + 1.0);
    scene.cell.walls = {testing::Floor(), Wall{Vec2(4.5, 0.0), Vec2(1.0, 0.0)},
                        Wall{Vec2(5.5, 0.0), Vec2(-1.0, 0.0)}};
    scene.effects.gravity = Vec2(0.0, -1.0);
    for (int i = 0; i < k; ++i) scene.particles.push_back(Disk(5.0, 0.5 + i, 0.5));
    scene = WithStaticForces(scene);
    PerturbationOptions o;
    const PerturbationBase base = PreparePerturbations(scene, o);
    const double m = scene.particles[0].Mass();
    const PerturbationResult lift = Perturb(base, ParticleShift(base, 0, Vec2(0.0, 1.0)), o);
    ASSERT_EQ(lift.status, PerturbationStatus::kOk) << "k = " << k << ": " << lift.solve.message;
    EXPECT_NEAR(lift.f_crit, (k - 1) * m * (1.0 + o.gap / (o.dt * o.dt)), 1e-12 * k) << "k = " << k;
    EXPECT_NEAR(lift.f_reference, k * m, 1e-10 * k)
        << "k = " << k;  // F_y: the floor carries the column
    for (int i = 1; i < k; ++i)
      EXPECT_LT((lift.displacement[i] - Vec2(0.0, o.gap)).norm(), 1e-3 * o.gap) << i;
    // All k disks move by ξ, the lifted one (at the origin) included: δ = Σ i / k = (k − 1)/2.
    EXPECT_EQ(lift.displacement[0], Vec2(0.0, o.gap));
    EXPECT_NEAR(lift.penetration_depth, (k - 1) / 2.0, 1e-3) << "k = " << k;
    const PerturbationResult push = Perturb(base, ParticleShift(base, k - 1, Vec2(0.0, -1.0)), o);
    EXPECT_EQ(push.status, PerturbationStatus::kBlocked) << "k = " << k << ": " << push.f_crit;
    EXPECT_EQ(push.solve.backend, k == 1 ? "known motion" : "kinematic LP") << "k = " << k;
  }
}

// A disk on two fixed supports (nothing else moves): lifting it needs no force and its
// response (nothing moves but the disk) is linear; pushing it down would drive it into
// the fixed disks, which the step cannot stop, so it is blocked before any solve.
TEST(Perturbation, ShiftingADiskOnFixedSupports) {
  const Scene scene = VGroove(1.2);
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const PerturbationResult up = Perturb(base, ParticleShift(base, 2, Vec2(0.0, 1.0)), o);
  EXPECT_EQ(up.status, PerturbationStatus::kOk) << up.solve.message;
  EXPECT_EQ(up.f_crit, 0.0);
  EXPECT_EQ(up.linearity_misfit, 0.0);
  const PerturbationResult down = Perturb(base, ParticleShift(base, 2, Vec2(0.0, -1.0)), o);
  EXPECT_EQ(down.status, PerturbationStatus::kBlocked);
  EXPECT_TRUE(std::isnan(down.f_crit));
  EXPECT_NE(down.solve.message.find("neither of which can give way"), std::string::npos)
      << down.solve.message;
  EXPECT_THROW(ParticleShift(base, 0, Vec2(0.0, 1.0)), std::invalid_argument);  // fixed
  EXPECT_THROW(ParticleShift(base, 3, Vec2(0.0, 1.0)), std::invalid_argument);  // no such particle
}

// Two columns on fixed disks, periodic in x and two diameters wide each: one bin per column.
// Left: fixed 0, free 1 and 2 above it; right: fixed 3, free 4.
Scene TwoColumns() {
  Scene s;
  s.cell.size = Vec2(4.4, 20.0);
  s.cell.periodicity = Periodicity::kX;
  s.effects.gravity = Vec2(0.0, -1.0);
  s.particles = {Disk(1.0, 1.0, 1.0, true), Disk(1.0, 3.0, 1.0), Disk(1.0, 5.0, 1.0),
                 Disk(3.2, 1.0, 1.0, true), Disk(3.2, 3.0, 1.0)};
  return WithStaticForces(s);
}

// The selection `perturb` and `bounds` share: per bin the highest free disk pushed down
// (top) or the lowest free one pushed up (bottom), in bin order; one named particle down or
// up, refused naming the option when fixed or missing.
TEST(Perturbation, ShiftSelectionsPickPerBinOrTheNamedParticle) {
  const PerturbationBase base = PreparePerturbations(TwoColumns(), PerturbationOptions{});
  using Kind = ShiftSelection::Kind;
  auto picked = [&](ShiftSelection selection) {
    std::vector<std::pair<int, double>> out;  // particle, vertical direction
    for (const PerturbationTarget& t : ShiftTargets(base, selection)) {
      EXPECT_EQ(t.kind, PerturbationTarget::Kind::kParticleShift);
      EXPECT_EQ(t.direction.x(), 0.0);
      out.emplace_back(t.i, t.direction.y());
    }
    return out;
  };
  using Picks = std::vector<std::pair<int, double>>;
  EXPECT_EQ(picked({Kind::kTop}), (Picks{{2, -1.0}, {4, -1.0}}));
  EXPECT_EQ(picked({Kind::kBottom}), (Picks{{1, 1.0}, {4, 1.0}}));
  EXPECT_EQ(picked({Kind::kDown, 2}), (Picks{{2, -1.0}}));
  EXPECT_EQ(picked({Kind::kUp, 1}), (Picks{{1, 1.0}}));
  EXPECT_EQ(ToString(ShiftSelection{Kind::kTop}), "top");
  EXPECT_EQ(ToString(ShiftSelection{Kind::kDown, 2}), "shift-down 2");
  auto refusal = [&](ShiftSelection selection) {
    try {
      ShiftTargets(base, selection);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal({Kind::kDown, 3}), "--shift-down 3: particle 3 is fixed and cannot be shifted");
  EXPECT_EQ(refusal({Kind::kUp, 5}),
            "--shift-up 5: particle 5 does not exist: the packing has 5 particles (0..4)");
}

TEST(Perturbation, ResultsDoNotDependOnTheThreadCount) {
  const Scene scene = VGroove(1.3);
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const std::vector<PerturbationTarget> targets = {Opening(0, 2), Opening(1, 2), Opening(0, 2)};
  std::vector<double> one, two;
  PerturbAll(base, targets, o, 1,
             [&](int, const PerturbationResult& r) { one.push_back(r.f_crit); });
  PerturbAll(base, targets, o, 2, [&](int k, const PerturbationResult& r) {
    EXPECT_EQ(k, static_cast<int>(two.size()));  // in target order
    two.push_back(r.f_crit);
  });
  ASSERT_EQ(one.size(), 3u);
  EXPECT_EQ(one, two);
}

// A long run reports results as they finish (each record written at once): every target
// exactly once, with the results of the ordered run.
TEST(Perturbation, AsFinishedReportsEveryTargetOnceWithTheOrderedResults) {
  const Scene scene = VGroove(1.3);
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const std::vector<PerturbationTarget> targets = {Opening(0, 2), Opening(1, 2), Opening(0, 2),
                                                   Opening(1, 2), Opening(0, 2)};
  std::vector<double> ordered;
  PerturbAll(base, targets, o, 1,
             [&](int, const PerturbationResult& r) { ordered.push_back(r.f_crit); });
  PerturbSchedule schedule;
  schedule.threads = 2;
  schedule.as_finished = true;
  std::map<int, double> finished;
  PerturbAll(base, targets, o, schedule, [&](int k, const PerturbationResult& r) {
    EXPECT_TRUE(finished.emplace(k, r.f_crit).second) << "target " << k << " reported twice";
  });
  ASSERT_EQ(finished.size(), targets.size());
  for (int k = 0; k < static_cast<int>(targets.size()); ++k)
    EXPECT_EQ(finished[k], ordered[k]) << k;
}

// A caller that cannot take a result (its records file fails) gets its error back from
// every schedule, after the workers are joined; no perturbation is reported after it.
TEST(Perturbation, AnErrorOfTheCallerIsPassedOnAndStopsTheRun) {
  const Scene scene = VGroove(1.3);
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const std::vector<PerturbationTarget> targets(6, Opening(0, 2));
  for (const int threads : {1, 2}) {
    for (const bool as_finished : {false, true}) {
      PerturbSchedule schedule;
      schedule.threads = threads;
      schedule.as_finished = as_finished;
      int reported = 0;
      EXPECT_THROW(PerturbAll(base, targets, o, schedule,
                              [&](int, const PerturbationResult&) {
                                ++reported;
                                throw std::runtime_error("disk full");
                              }),
                   std::runtime_error);
      EXPECT_EQ(reported, 1) << threads << " threads, as finished " << as_finished;
    }
  }
}

// A run's budget (--time-limit): no target starts once it is spent, in either order.
TEST(Perturbation, NoTargetStartsOnceTheBudgetIsSpent) {
  const Scene scene = VGroove(1.3);
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  for (const int threads : {1, 2}) {
    for (const bool as_finished : {false, true}) {
      PerturbSchedule schedule;
      schedule.threads = threads;
      schedule.as_finished = as_finished;
      schedule.start_before = std::chrono::steady_clock::now();
      int reported = 0;
      PerturbAll(base, {Opening(0, 2), Opening(1, 2)}, o, schedule,
                 [&](int, const PerturbationResult&) { ++reported; });
      EXPECT_EQ(reported, 0) << threads << " threads, as finished " << as_finished;
    }
  }
}

// On one thread each result is reported before the next perturbation starts (a long run
// records what it has solved when a later perturbation fails or the run is killed).
TEST(Perturbation, OneThreadReportsEachResultBeforeTheNext) {
  const Scene scene = VGroove(1.2);
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  int reported = 0;
  EXPECT_THROW(PerturbAll(base, {Opening(0, 2), Opening(0, 9)}, o, 1,
                          [&](int, const PerturbationResult&) { ++reported; }),
               std::invalid_argument);
  EXPECT_EQ(reported, 1);
}

TEST(Perturbation, BadTargetsAndOptionsAreRefused) {
  const Scene scene = VGroove(1.2);
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  EXPECT_THROW(Perturb(base, Opening(0, 7), o), std::invalid_argument);
  EXPECT_THROW(Perturb(base, Shift(0, Vec2(0.0, 1.0)), o), std::invalid_argument);  // fixed
  PerturbationOptions bad = o;
  bad.gap = -1e-9;
  EXPECT_THROW(Validate(bad), std::invalid_argument);
  Scene bare = scene;
  bare.forces.clear();
  EXPECT_THROW(PreparePerturbations(bare, o), std::invalid_argument);
}

TEST(Perturbation, SampleIsDeterministicAndOrdered) {
  std::vector<PerturbationTarget> all(50);
  for (int k = 0; k < 50; ++k) all[k].i = k;
  const auto a = SampleTargets(all, 10, 7), b = SampleTargets(all, 10, 7),
             c = SampleTargets(all, 10, 8);
  ASSERT_EQ(a.size(), 10u);
  for (int k = 0; k < 10; ++k) EXPECT_EQ(a[k].i, b[k].i);
  for (int k = 1; k < 10; ++k) EXPECT_LT(a[k - 1].i, a[k].i);
  bool differs = false;
  for (int k = 0; k < 10; ++k) differs |= a[k].i != c[k].i;
  EXPECT_TRUE(differs);
}

// Frictionless jammed packings are isostatic: the forces are unique, so holding a contact
// open takes exactly its static force, at fixed pressure as at fixed volume.
TEST(Perturbation, FrictionlessPackingOpeningsCarryTheStaticForce) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.unjam");
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const std::vector<PerturbationTarget> targets = SampleTargets(ContactTargets(base), 2, 3);
  std::vector<ReducedResponse> records;
  const ResponseLayout layout = MakeLayout(base, EnsembleOptions{}, o.gap);
  for (const PerturbationTarget& t : targets) {
    const PerturbationResult r = Perturb(base, t, o);
    ASSERT_EQ(r.status, PerturbationStatus::kOk) << r.solve.residual;
    EXPECT_NEAR(r.f_crit / r.f_reference, 1.0, 1e-5);
    // Virtual work over the step: the excess over F_cont is the inertia of the mechanism
    // (grains and cell), linear in ξ. Here a tenth of a percent of it is the cell's, and
    // the two sides agree to 1.4e-5 of it or better.
    EXPECT_GT(r.inertial_force, 0.0);
    EXPECT_NEAR(r.f_crit - r.f_reference, r.inertial_force, 1e-4 * r.inertial_force);
    EXPECT_GT(r.penetration_depth, 0.0);
    records.push_back(Reduce(base, r, layout, EnsembleOptions{}));
  }
  const EnsembleSummary summary = Summarize(records, layout, EnsembleOptions{});
  EXPECT_EQ(summary.used, 2);
  EXPECT_NEAR(summary.ratio, 1.0, 1e-6);
  // At fixed volume the static network f⁰ is a self-stress of the frozen cell (every grain
  // balanced, no load), so by virtual work f⁰·u_n = 0 for every motion: opening the
  // contact (u_n > 0 there) would close another carrying one. Rigid grains cannot do it.
  // (Newton used to report F_crit ≈ F_cont here, with ~1e-12 penetrations spread over
  // every contact, each below its tolerance.)
  PerturbationOptions volume = o;
  volume.cell = CellCondition::kFixedVolume;
  for (const PerturbationTarget& t : targets) {
    const PerturbationResult v = Perturb(base, t, volume);
    EXPECT_EQ(v.status, PerturbationStatus::kBlocked) << v.f_crit;
    EXPECT_TRUE(std::isnan(v.f_crit));
  }
}

// The small-gap check on a frictional packing. The quasi-static response of a rigid
// step is linear in ξ: ten times the gap moves every grain ten times as far (measured: to
// 2.4e-6 of the largest displacement), and F_crit does not change (measured: by 6e-9 of
// itself). Contact 17–53 of the default packing (μ = 0.5) opens quasi-statically (lemke,
// the default there). Unlike a frictionless opening, F_crit does not grow by the
// mechanism's inertial part here (5e-8 at ξ = 1e-9): friction, not the held contact,
// takes it up.
TEST(Perturbation, FrictionalQuasiStaticOpeningIsLinearInTheGap) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  PerturbationOptions o;
  o.check_linearity = false;  // the test is that check, made here by hand
  const PerturbationBase base = PreparePerturbations(scene, o);
  const PerturbationTarget target = OpeningOf(base, 17, 53);
  ASSERT_EQ(target.i, 17);
  PerturbationOptions ten = o;
  ten.gap = 10.0 * o.gap;
  const PerturbationResult r = Perturb(base, target, o);
  const PerturbationResult r10 = Perturb(base, target, ten);
  ASSERT_EQ(r.status, PerturbationStatus::kOk) << r.solve.message;
  ASSERT_EQ(r10.status, PerturbationStatus::kOk) << r10.solve.message;
  EXPECT_NEAR(r10.f_crit, r.f_crit, 1e-6 * r.f_crit);
  double largest = 0.0, misfit = 0.0;
  for (std::size_t i = 0; i < r.displacement.size(); ++i) {
    largest = std::max(largest, r10.displacement[i].norm());
    misfit = std::max(misfit, (r10.displacement[i] - 10.0 * r.displacement[i]).norm());
  }
  EXPECT_GT(largest, 0.5 * ten.gap);
  EXPECT_LT(misfit, 1e-4 * largest);
  EXPECT_NEAR(r10.penetration_depth, r.penetration_depth, 1e-6 * r.penetration_depth);
}

// --check-linearity applies that test to each quasi-static response. Contact 139–286 of
// the same packing opens with an inertia ratio of 6e-7, below the 1e-6 of a quasi-static
// step, but its motion is 600 ξ and does not scale with ξ: the stick/slide/open pattern
// of the answer at ξ does not solve the step at 10ξ (residual 6.7e-9 against 1e-10), the
// path from it ends on another motion, at 14 times the misfit allowed, and F_crit changes
// by 0.024. It is reported as "nonlinear".
TEST(Perturbation, CheckLinearityRejectsAResponseThatDoesNotScaleWithTheGap) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const PerturbationTarget target = OpeningOf(base, 139, 286);
  ASSERT_EQ(target.i, 139);
  o.check_linearity = true;
  const PerturbationResult r = Perturb(base, target, o);
  EXPECT_TRUE(r.resolved && r.quasi_static) << r.status;
  EXPECT_FALSE(r.linear);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.status, PerturbationStatus::kNonlinear);
  EXPECT_GT(r.linearity_misfit, 1.0);
  EXPECT_GT(std::abs(r.fcrit_10xi - r.f_crit), 1e-3 * base.mean_contact_force);
}

// The check continues the answer at ξ: the step at 10ξ is solved first on the answer's
// own basis (its stick/slide/open pattern). Contact 3–447 of the default packing is
// linear on it (the same basis solves the step at 10ξ to residual 1e-15; the motion
// scales to 2e-7). Solved from zero impulses instead (check_by_continuation = false,
// `--cold-check`), the step at 10ξ ends on another member of its family of solutions
// (misfit 0.43, F_crit 1.678 against 1.477), which the cold check calls nonlinear: the
// answer is one member, and which member a path from zero picks depends on ξ.
TEST(Perturbation, TheSmallGapCheckContinuesTheAnswerOnItsBasis) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  PerturbationOptions o;
  o.backend = "lemke";
  const PerturbationBase base = PreparePerturbations(scene, o);
  const PerturbationTarget target = OpeningOf(base, 3, 447);
  ASSERT_EQ(target.i, 3);
  ASSERT_TRUE(o.check_linearity && o.check_by_continuation);  // the defaults
  const PerturbationResult r = Perturb(base, target, o);
  ASSERT_EQ(r.status, PerturbationStatus::kOk) << r.solve.message;
  EXPECT_LT(r.linearity_misfit, 1e-5);
  EXPECT_NEAR(r.fcrit_10xi, r.f_crit, 1e-4 * r.f_crit);
  EXPECT_NE(r.solve.message.find("10 xi check: Lemke: the given basis: residual"),
            std::string::npos)
      << r.solve.message;
  PerturbationOptions cold = o;
  cold.check_by_continuation = false;
  const PerturbationResult c = Perturb(base, target, cold);
  EXPECT_EQ(c.f_crit, r.f_crit);  // the same answer at ξ
  EXPECT_EQ(c.status, PerturbationStatus::kNonlinear) << c.linearity_misfit;
  EXPECT_GT(c.linearity_misfit, 0.1);
}

// Lemke's paths on a pile take up the gravity load of every contact from zero impulses:
// up to 7.5 pivots per complementarity row on these shifts. A per-run bound of 3 per row
// left 6 of the 10 top shifts unresolved; every shift must be resolved (quasi-static or
// dynamic), and pushing a grain down into the pile or up off its support takes a force.
TEST(Perturbation, LemkeResolvesEveryShiftOfTheSmallPile) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/gravity-n100-mu0.5.unjam");
  PerturbationOptions o;
  o.backend = "lemke";
  const PerturbationBase base = PreparePerturbations(scene, o);
  std::vector<PerturbationTarget> targets = TopTargets(base);
  const std::vector<PerturbationTarget> bottom = BottomTargets(base);
  targets.insert(targets.end(), bottom.begin(), bottom.end());
  ASSERT_EQ(targets.size(), 20u);
  for (const PerturbationTarget& t : targets) {
    const PerturbationResult r = Perturb(base, t, o);
    EXPECT_TRUE(r.resolved) << t.i << ": " << r.solve.message;
    EXPECT_EQ(r.solve.backend, "lemke");
    EXPECT_GT(r.f_crit, 0.0) << t.i;
  }
}

// The rule `--member nearest` (PerturbationOptions::nearest_member): the answer's member
// of its family is replaced by the one with the same motion pattern nearest the static
// forces (the pattern LP). On the small pile's top shift of particle 33 (quasi-static,
// linear) that is another member, whose impulses differ by up to 4.5, and whose F_crit and
// displacements are those of the path's answer: by virtual work, a self-stress that keeps
// the pattern changes F_crit only through the normal forces of sliding contacts.
TEST(Perturbation, TheNearestMemberOfTheMotionPatternKeepsTheCriticalForce) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/gravity-n100-mu0.5.unjam");
  PerturbationOptions path;
  path.backend = "lemke";
  const PerturbationBase base = PreparePerturbations(scene, path);
  const PerturbationTarget target = TopTargets(base)[5];
  ASSERT_EQ(target.i, 33);
  PerturbationOptions nearest = path;
  nearest.nearest_member = true;
  const PerturbationResult a = Perturb(base, target, path);
  const PerturbationResult b = Perturb(base, target, nearest);
  ASSERT_EQ(a.status, PerturbationStatus::kOk) << a.solve.message;
  ASSERT_EQ(b.status, PerturbationStatus::kOk) << b.solve.message;
  EXPECT_EQ(b.solve.backend, "lemke+pattern");
  EXPECT_NEAR(b.f_crit, a.f_crit, 1e-9 * a.f_crit);
  EXPECT_NEAR(b.fcrit_10xi, b.f_crit, 1e-6 * b.f_crit);
  double moved = 0.0, change_a = 0.0, change_b = 0.0, largest_difference = 0.0;
  for (std::size_t i = 0; i < a.displacement.size(); ++i)
    moved = std::max(moved, (b.displacement[i] - a.displacement[i]).norm());
  EXPECT_LT(moved, 1e-2 * path.gap);
  ASSERT_EQ(a.force_changes.size(), b.force_changes.size());
  for (std::size_t k = 0; k < a.force_changes.size(); ++k) {
    const ContactForceChange &x = a.force_changes[k], &y = b.force_changes[k];
    change_a += std::abs(x.normal_after - x.normal_before) +
                std::abs(x.tangential_after - x.tangential_before);
    change_b += std::abs(y.normal_after - y.normal_before) +
                std::abs(y.tangential_after - y.tangential_before);
    largest_difference = std::max(largest_difference, std::abs(y.normal_after - x.normal_after));
  }
  EXPECT_GT(largest_difference,
            1e6 * path.gap);      // another member, not the O(ξ) response (pattern_lp_test)
  EXPECT_LT(change_b, change_a);  // nearer the static forces
}

// On the hyperstatic μ = 0.1 packing (829 contacts, 285 self-stresses) the path from zero
// impulses of this opening (contact 8–108, F_cont = 1.315) cycles at every tie tolerance:
// the lexicographic order of its degenerate bases is below double precision. A perturbed
// run (lemke.cpp) resolves it. Its admissible interval (`unjam bounds --contacts K`) is
// [0, 3.007] without friction.
// Opens the `index`-th force-carrying contact of the bundled μ = 0.1 packing (default
// options), which must be the contact (i, j).
void OpenContactOfTheMu01Packing(std::size_t index, int i, int j, PerturbationResult& r) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.1.unjam");
  PerturbationOptions o;
  o.backend = "lemke";
  o.check_linearity = false;  // these tests are about resolving one step; the check doubles it
  const PerturbationBase base = PreparePerturbations(scene, o);
  const std::vector<PerturbationTarget> all = ContactTargets(base);
  ASSERT_GT(all.size(), index);
  const PerturbationTarget& t = all[index];
  ASSERT_EQ(t.i, i);
  ASSERT_EQ(t.j, j);
  r = Perturb(base, t, o);
}

TEST(Perturbation, LemkeResolvesAnOpeningWhosePathFromZeroCycles) {
  PerturbationResult r;
  ASSERT_NO_FATAL_FAILURE(OpenContactOfTheMu01Packing(27, 8, 108, r));
  ASSERT_TRUE(r.resolved) << r.solve.message;
  EXPECT_EQ(r.solve.backend, "lemke");
  EXPECT_NE(r.solve.message.find("cold, ties 1e-16: cycle"), std::string::npos) << r.solve.message;
  EXPECT_GE(r.f_crit, r.f_reference);
  EXPECT_LE(r.f_crit, 3.007 * (1.0 + 1e-3));
}

// On the same packing the opening of contact 40–317 (F_cont = 0.022) defeats the slip-speed
// form: its paths from zero cycle (in the step's units and in the rate form) and Newton's
// polish of the perturbed run stalls (2.4e-11 against 5.3e-12). The shifted-box form
// (lemke.cpp), whose sticking contacts are not degenerate, solves it on its first path from
// zero, exactly (in the rate form, whose runs come first). The answer must be a solution to
// round-off and lie in the contact's admissible interval [0, 0.9519] without friction
// (`unjam bounds --contacts K`).
TEST(Perturbation, LemkeBoxFormResolvesAnOpeningTheSlipFormCannot) {
  PerturbationResult r;
  ASSERT_NO_FATAL_FAILURE(OpenContactOfTheMu01Packing(133, 40, 317, r));
  ASSERT_TRUE(r.resolved) << r.solve.message;
  const std::string& m = r.solve.message;
  const std::string box_path = "box form, cold, ties 1e-16";
  const std::size_t box = m.find(box_path + ": solved");
  ASSERT_NE(box, std::string::npos) << m;
  EXPECT_EQ(m.find(": solved"), box + box_path.size()) << m;  // no earlier run solved it
  EXPECT_LT(r.solve.residual, 1e-13);
  EXPECT_GE(r.f_crit, 0.0);
  EXPECT_LE(r.f_crit, 0.9519 * (1.0 + 1e-3));
}

// F_crit of a shift lies in the shift's interval over the admissible force networks
// (indeterminacy/shift_bounds.hpp), to 1e-6.
void ExpectInsideTheShiftsLpInterval(const EquilibriumSystem& system, const PerturbationTarget& t,
                                     double f_crit) {
  const ShiftBoundsReport lp = ComputeShiftBounds(system, {{t.i, t.direction}}, {});
  ASSERT_TRUE(lp.feasible && lp.bounds[0].min.ok() && lp.bounds[0].max.ok()) << lp.message;
  EXPECT_GE(f_crit, lp.bounds[0].min.value - 1e-6) << t.i;
  EXPECT_LE(f_crit, lp.bounds[0].max.value + 1e-6) << t.i;
}

// The top shift of `particle` (the highest particle of its bin, pushed down).
PerturbationTarget TopShiftOf(const PerturbationBase& base, int particle) {
  for (const PerturbationTarget& t : TopTargets(base)) {
    if (t.i == particle) return t;
  }
  return {};
}

// The tall narrow pile (problems/gravity-n200-w8-mu0.1: 200 disks 8 wide, μ = 0.1). On
// the top shifts of particles 170, 24 and 78 Lemke's path from zero impulses in the step's
// own units cycles or ends on a ray; in the rate form (velocities in units of ξ/Δt,
// lemke.cpp) the path from zero solves each exactly. Each answer must be linear in ξ (the
// small-gap check keeps it: status "ok") and its F_crit must lie in the shift's interval
// over the admissible force networks (indeterminacy/shift_bounds.hpp).
TEST(Perturbation, LemkeInRateUnitsResolvesTallPileShiftsThePlainPathCannot) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/gravity-n200-w8-mu0.1.unjam");
  PerturbationOptions o;
  o.backend = "lemke";
  o.fallback = "none";
  const PerturbationBase base = PreparePerturbations(scene, o);
  const EquilibriumSystem system = BuildEquilibriumSystem(scene);
  int checked = 0;
  for (const PerturbationTarget& t : TopTargets(base)) {
    if (t.i != 170 && t.i != 24 && t.i != 78) continue;
    ++checked;
    const PerturbationResult r = Perturb(base, t, o);
    const std::string& m = r.solve.message;
    ASSERT_EQ(r.status, PerturbationStatus::kOk) << t.i << ": " << m;
    const std::string plain = "Lemke: cold, ties 1e-16: ";
    ASSERT_EQ(m.rfind(plain, 0), 0u) << m;
    EXPECT_NE(m.compare(plain.size(), 6, "solved"), 0) << m;
    EXPECT_NE(m.find("; rate form, cold, ties 1e-16: solved"), std::string::npos) << m;
    EXPECT_LT(r.solve.residual, 1e-13);
    ExpectInsideTheShiftsLpInterval(system, t, r.f_crit);
  }
  EXPECT_EQ(checked, 3);
}

// A pile at μ = 1 (problems/gravity-n400-w25-mu1: 400 disks 25 wide, as tall as the
// 1600-disk piles). Its particle 206 hangs by friction between grains 32 and 275, whose
// contacts are 22–25° above its centre, so that every step from rest also has a solution
// in which 206 falls freely: no impulse on it, d = (0, −g Δt²) (implicit Euler from rest).
// On the top shift of particle 143 Lemke's first path ends on that member (the step is
// "dynamic"), exactly: 206 moves by −g Δt² to round-off.
TEST(Perturbation, LemkesFirstPathEndsOnTheMemberInWhichAHangingGrainFalls) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/gravity-n400-w25-mu1.unjam");
  PerturbationOptions o;
  o.backend = "lemke";
  o.fallback = "none";
  const PerturbationBase base = PreparePerturbations(scene, o);
  const PerturbationTarget target = TopShiftOf(base, 143);
  ASSERT_EQ(target.i, 143);

  const PerturbationResult path = Perturb(base, target, o);
  ASSERT_TRUE(path.resolved) << path.solve.message;
  EXPECT_EQ(path.status, PerturbationStatus::kDynamic);
  const double g_dt2 = 1.0 * o.dt * o.dt;
  EXPECT_NEAR(path.displacement[206].x(), 0.0, 1e-9 * g_dt2);
  EXPECT_NEAR(path.displacement[206].y(), -g_dt2, 1e-9 * g_dt2);
}

}  // namespace
}  // namespace unjam
