// Tests for src/stepping/simulation.cpp with a pressure bath: positions and branch vectors
// across the periodic boundary while the cell changes size.
#include <gtest/gtest.h>

#include <cmath>

#include "test_scenes.hpp"
#include "unjam/stepping/simulation.hpp"

namespace unjam {
namespace {

using testing::Disk;

// Two disks far apart across x = 0 in a fully periodic cell that the bath compresses.
Scene PairAcrossTheBoundary() {
  Scene s;
  s.cell.size = Vec2(12.0, 12.0);
  s.cell.periodicity = Periodicity::kXY;
  s.effects.pressure_bath = PressureBath{1.0, 10.0, -0.05};
  s.particles = {Disk(0.6, 6.0, 0.5), Disk(11.0, 6.0, 0.5)};  // 1.6 apart across the boundary
  return s;
}

TEST(PeriodicCell, AffineCompressionScalesPositionsAndTheCellTogether) {
  Simulation sim(PairAcrossTheBoundary(), StepOptions{});
  const Vec2 x0 = sim.scene().particles[0].position;
  const Vec2 x1 = sim.scene().particles[1].position;
  const double l0 = sim.scene().cell.size.x();
  sim.Step();
  const double rate = sim.scene().effects.pressure_bath->strain_rate;
  const double stretch = 1.0 + sim.options().dt * rate;
  EXPECT_LT(rate, -0.05);  // the bath keeps compressing: no internal pressure yet
  EXPECT_DOUBLE_EQ(sim.scene().cell.size.x(), l0 * stretch);
  EXPECT_DOUBLE_EQ(sim.scene().particles[0].position.x(), x0.x() * stretch);
  EXPECT_DOUBLE_EQ(sim.scene().particles[1].position.x(), x1.x() * stretch);
  // The minimum-image separation shrinks by the same factor.
  const double separation = sim.scene().particles[0].position.x() + sim.scene().cell.size.x() -
                            sim.scene().particles[1].position.x();
  EXPECT_NEAR(separation, 1.6 * stretch, 1e-12);
}

TEST(PeriodicCell, PairAcrossTheBoundaryMeetsAndHoldsThePressure) {
  Simulation sim(PairAcrossTheBoundary(), StepOptions{});
  // The cell shrinks until the pair touches across x = 0 (only the x images matter:
  // in y each disk also sees itself, but the cell stays far larger than a diameter).
  bool touched = false;
  for (int n = 0; n < 20000 && !touched; ++n) {
    sim.Step();
    for (std::size_t k = 0; k < sim.contacts().size(); ++k) {
      const Contact& c = sim.contacts()[k];
      if (sim.impulses()[k][0] > 0.0) {
        touched = true;
        EXPECT_NE(c.image[0], 0);
        // Branch vector across the image: centre to centre, length R_i + R_j + gap.
        EXPECT_NEAR(c.center_to_center.norm(), 1.0 + c.gap, 1e-12);
        EXPECT_NEAR(std::abs(c.center_to_center.x()), c.center_to_center.norm(), 1e-9);
      }
    }
  }
  ASSERT_TRUE(touched);
  for (const Contact& c : DetectContacts(sim.scene(), 0.0)) EXPECT_GT(c.gap, -1e-9);
}

}  // namespace
}  // namespace unjam
