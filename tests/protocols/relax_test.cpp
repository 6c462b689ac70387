// Tests for src/protocols/relax.cpp: the certificate (its refinement of the last step's
// forces, the LP, the closure gap), the protocol's time step and units.
#include <gtest/gtest.h>

#include <utility>

#include "../test_scenes.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/gravity_pile.hpp"
#include "unjam/protocols/pressure_packing.hpp"
#include "unjam/protocols/relax.hpp"

namespace unjam {
namespace {

// One certificate of `scene` after a single dynamics step of 1e-6, too short to move
// anything measurable (particles move by at most ~1e-8): the step's forces are the reference.
RelaxReport CertifyAfterOneTinyStep(Scene scene, RelaxOptions relax) {
  StepOptions step;
  step.dt = 1e-6;
  Simulation sim(std::move(scene), step);
  relax.window = 1;
  relax.max_steps = 1;
  return RelaxToStatic(sim, relax);
}

// The same on the bundled static packing, the step's solve cut to one sweep: the state is
// static, its forces are not.
RelaxReport CertifyAfterOneRoughStep(int refine_max_iterations, bool linear_program = false) {
  RelaxOptions relax;
  relax.step_max_iterations = 1;
  relax.refine_max_iterations = refine_max_iterations;
  relax.linear_program = linear_program;
  return CertifyAfterOneTinyStep(
      ReadPacking(UNJAM_SOURCE_DIR "/problems/pressure-n500-mu0.5.unjam"), relax);
}

TEST(Relax, LooseStepToleranceHoldsTheStepsGapsAboveTheProtocolTimeStep) {
  EXPECT_EQ(LooseStepTolerance(5e-3), 1e-4);
  EXPECT_EQ(LooseStepTolerance(kPackingTimeStep), 1e-4);
  EXPECT_DOUBLE_EQ(LooseStepTolerance(2.0 * kPackingTimeStep), 2.5e-5);
  // Above the protocol step, tolerance × Δt² (the size of the gaps a step's error
  // leaves) stays put.
  for (double dt : {0.03, 0.05, 0.1}) {
    EXPECT_NEAR(LooseStepTolerance(dt) * dt * dt, 1e-4 * kPackingTimeStep * kPackingTimeStep, 1e-20)
        << dt;
  }
}

TEST(Relax, TimeUnitIsTheMaxRadiusOverTheVelocityScale) {
  GasOptions gas;
  gas.pressure = 4.0;
  EXPECT_DOUBLE_EQ(TimeUnit(gas), 0.5);  // R_max √(ρ/P) with R_max = ρ = 1
  PileOptions pile;
  pile.gravity = 4.0;
  EXPECT_DOUBLE_EQ(TimeUnit(pile), 0.5);  // √(R_max/g)
  const Scene s = MakeGranularGas(gas);
  EXPECT_DOUBLE_EQ(TimeUnit(gas), 1.0 / VelocityScale(s));  // R_max = 1: the radii's bound
  EXPECT_LE(MaxRadius(s), 1.0);
}

Scene SmallPile() { return ReadPacking(UNJAM_SOURCE_DIR "/problems/gravity-n100-mu0.5.unjam"); }

int HighestFreeParticle(const Scene& pile) {
  int top = -1;
  for (int i = 0; i < static_cast<int>(pile.particles.size()); ++i) {
    if (pile.particles[i].fixed) continue;
    if (top < 0 || pile.particles[i].position.y() > pile.particles[top].position.y()) top = i;
  }
  return top;
}

TEST(Relax, RefinementStopsOnAParticleThatKeepsFalling) {
  Scene pile = SmallPile();
  pile.particles[HighestFreeParticle(pile)].position.y() +=
      0.05;  // lifted off its support: it falls in any step
  RelaxOptions o;
  o.refine_max_iterations = 30000;
  const Refinement r = RefineStaticForces(pile, pile.forces, o);
  EXPECT_TRUE(r.still_moving);
  // Two chunks show the same fall, or one whose step, solved exactly, has the grain falling.
  EXPECT_LE(r.sweeps, 2 * kRefineChunk);
}

TEST(Relax, RefinementOfAStaticPileRestoresItsForces) {
  const Scene pile = SmallPile();
  std::vector<ContactForce> halved = pile.forces;
  for (ContactForce& f : halved) {  // far from balance, on a static state
    f.normal *= 0.5;
    f.tangential *= 0.5;
  }
  RelaxOptions o;
  o.refine_max_iterations = 30000;
  const Refinement r = RefineStaticForces(pile, halved, o);
  EXPECT_FALSE(r.still_moving);
  EXPECT_GT(r.sweeps, 2 * kRefineChunk) << "not stopped where a moving state is";
  // The refined forces nearly balance the pile again: one sweep from them leaves a residual
  // far below one sweep from the halved ones, and no particle moving.
  auto one_sweep = [&](const std::vector<ContactForce>& forces) {
    Scene s = pile;
    s.forces = forces;
    StaticSolveOptions so;
    so.solver.nsgs.max_sweeps = 1;
    so.solver.nsgs.check_interval = 1;
    return SolveStatic(s, so);
  };
  const StaticSolution from_refined = one_sweep(r.forces), from_halved = one_sweep(halved);
  EXPECT_LT(from_refined.report.residual, 1e-3 * from_halved.report.residual);
  EXPECT_LT(from_refined.max_speed, o.rest_speed);
}

TEST(Relax, UnconvergedStepForcesFailTheCertificateWithoutRefinement) {
  const RelaxReport r = CertifyAfterOneRoughStep(0);
  EXPECT_EQ(r.static_checks, 1);
  EXPECT_FALSE(r.jammed);
  EXPECT_EQ(r.refined_checks, 0);
  EXPECT_NE(r.check_message.find("no admissible forces"), std::string::npos) << r.check_message;
}

TEST(Relax, RefiningTheStepForcesLetsTheStaticPackingPassInFull) {
  const RelaxReport r = CertifyAfterOneRoughStep(30000);
  EXPECT_EQ(r.static_checks, 1);
  EXPECT_EQ(r.refined_checks, 1);
  ASSERT_TRUE(r.jammed) << r.check_message;
  EXPECT_TRUE(r.final_check.report.converged());
  EXPECT_LT(r.final_check.equilibrium.residual, 1e-8);
  EXPECT_LT(r.pressure_mismatch, 1e-8);
}

TEST(Relax, TheLinearProgramFindsTheNetworkTheProjectionMisses) {
  // The same rough forces as above: too far from every admissible network for the
  // projection, but the packing is static, and the LP (nearest in L1) finds one.
  const RelaxReport r = CertifyAfterOneRoughStep(0, true);
  EXPECT_EQ(r.refined_checks, 0);
  ASSERT_TRUE(r.jammed) << r.check_message;
  EXPECT_TRUE(r.final_check.report.converged());
  EXPECT_LT(r.final_check.equilibrium.residual, 1e-8);
  EXPECT_LT(r.pressure_mismatch, 1e-8);
}

// Disk 2 of a V-groove (fixed disks 0 and 1 at x = ∓1.2) moved left until it touches disk 0
// and stands `gap` off disk 1. One contact cannot hold it: its normal is not vertical, and a
// tangential force would turn the disk.
Scene GrooveWithOneSupportApart(double gap) {
  const double a = 1.2;
  Scene s = testing::VGroove(a, 0.5);
  // Touching disk 0 at x = −δ, the distance to disk 1 is √(4 + 4aδ): δ = ((2 + gap)² − 4) / 4a.
  const double delta = ((2.0 + gap) * (2.0 + gap) - 4.0) / (4.0 * a);
  s.particles[2].position = Vec2(-delta, std::sqrt(4.0 - (a - delta) * (a - delta)));
  return s;
}

// One certificate of that state, its second support 5e-5 away.
RelaxReport CertifyGroove(double closure_gap, bool linear_program) {
  RelaxOptions relax;
  relax.closure_gap = closure_gap;
  relax.linear_program = linear_program;
  return CertifyAfterOneTinyStep(GrooveWithOneSupportApart(5e-5), relax);
}

TEST(Relax, TheClosureGapDecidesWhichContactsMayCarryForce) {
  // Within 1e-6 only one contact: no network, and the LP proves it.
  EXPECT_FALSE(CertifyGroove(1e-6, false).jammed);
  const RelaxReport near = CertifyGroove(1e-6, true);
  EXPECT_FALSE(near.jammed);
  EXPECT_NE(near.check_message.find("not static"), std::string::npos) << near.check_message;
  // Within 1e-4 the second contact is detected and loaded (the certificate detects contacts
  // up to the closure gap), the closure moves the disk by about the gap, and the closed
  // groove is proven static.
  const RelaxReport wide = CertifyGroove(1e-4, false);
  ASSERT_TRUE(wide.jammed) << wide.check_message;
  EXPECT_GT(wide.closure_displacement, 1e-5);
  EXPECT_LT(wide.closure_displacement, 1e-4);
  EXPECT_LT(wide.final_check.equilibrium.residual, 1e-8);
  ASSERT_EQ(wide.final_check.contacts.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_LE(std::abs(wide.final_check.contacts[k].gap), 1e-9);
    EXPECT_GT(wide.final_check.forces[k].x(), 0.1);  // both carry the weight, π
  }
}

}  // namespace
}  // namespace unjam
