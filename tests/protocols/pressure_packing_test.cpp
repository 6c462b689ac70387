// Tests for src/protocols/pressure_packing.cpp and relax.cpp: small packings jammed at
// constant pressure.
#include <gtest/gtest.h>

#include "unjam/analysis/equilibrium.hpp"
#include "unjam/protocols/pressure_packing.hpp"
#include "unjam/protocols/relax.hpp"

namespace unjam {
namespace {

struct Jammed {
  Scene scene;
  RelaxReport report;
};

Jammed JamSmallPacking(double mu, std::uint64_t seed) {
  GasOptions gas;
  gas.particles = 40;
  gas.friction = mu;
  gas.pressure = 2.0;
  gas.seed = seed;
  StepOptions step;
  step.dt = 1e-2;
  Simulation sim(MakeGranularGas(gas), step);
  RelaxOptions relax;
  relax.max_steps = 200000;
  Jammed out;
  out.report = RelaxToStatic(sim, relax);
  out.scene = sim.scene();
  return out;
}

TEST(PressurePacking, GasStartsDiluteAtRestWithoutOverlap) {
  GasOptions gas;
  gas.particles = 200;
  const Scene s = MakeGranularGas(gas);
  EXPECT_EQ(s.cell.periodicity, Periodicity::kXY);
  EXPECT_FALSE(s.effects.gravity.has_value());
  EXPECT_NEAR(PackingFraction(s), 0.3, 1e-12);
  EXPECT_TRUE(DetectContacts(s, 0.0).empty());
  for (const Particle& p : s.particles) {
    EXPECT_GE(p.radius, 0.5);
    EXPECT_LE(p.radius, 1.0);
    EXPECT_EQ(p.velocity, Vec2::Zero());
  }
  gas.cell_mass = -1.0;
  EXPECT_THROW(MakeGranularGas(gas), std::invalid_argument);
}

TEST(PressurePacking, FrictionlessPackingJamsIsostaticAtTheExternalPressure) {
  const Jammed j = JamSmallPacking(0.0, 3);
  ASSERT_TRUE(j.report.jammed) << "steps " << j.report.steps;
  const StaticSolution& s = j.report.final_check;
  EXPECT_NEAR(s.equilibrium.pressure, 2.0, 2e-8);
  EXPECT_LT(s.equilibrium.residual, 1e-8);
  // Jammed frictionless disks in a periodic cell at fixed pressure are isostatic:
  // N_c = 2 (N' − 1) + 1 (two global translations, plus the cell's degree of freedom).
  const Coordination z = ComputeCoordination(j.scene, s.contacts, s.forces);
  const int carrying = static_cast<int>(j.scene.particles.size()) - z.rattlers;
  EXPECT_EQ(z.force_carrying_contacts, 2 * (carrying - 1) + 1);
  EXPECT_GT(PackingFraction(j.scene), 0.8);
  for (const Particle& p : j.scene.particles) EXPECT_EQ(p.velocity, Vec2::Zero());
}

TEST(PressurePacking, FrictionalPackingJamsLooserThanFrictionless) {
  const Jammed frictional = JamSmallPacking(1.0, 3);
  ASSERT_TRUE(frictional.report.jammed);
  EXPECT_NEAR(frictional.report.final_check.equilibrium.pressure, 2.0, 2e-8);
  const Jammed frictionless = JamSmallPacking(0.0, 3);
  EXPECT_LT(PackingFraction(frictional.scene), PackingFraction(frictionless.scene));
  const StaticSolution& s = frictional.report.final_check;
  const Coordination z = ComputeCoordination(frictional.scene, s.contacts, s.forces);
  EXPECT_LT(z.z, 4.0);
  EXPECT_GE(z.z, 3.0 - 1e-12);
}

TEST(PressurePacking, SameSeedSameBits) {
  const Jammed a = JamSmallPacking(0.5, 9);
  const Jammed b = JamSmallPacking(0.5, 9);
  ASSERT_EQ(a.scene.particles.size(), b.scene.particles.size());
  for (std::size_t i = 0; i < a.scene.particles.size(); ++i) {
    EXPECT_EQ(a.scene.particles[i].position, b.scene.particles[i].position);
  }
  EXPECT_EQ(a.scene.cell.size, b.scene.cell.size);
  EXPECT_EQ(a.report.steps, b.report.steps);
}

}  // namespace
}  // namespace unjam
