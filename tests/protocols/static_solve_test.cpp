// Tests for src/protocols/static_solve.cpp: static forces with known answers.
#include <gtest/gtest.h>

#include <cmath>

#include "test_scenes.hpp"
#include "unjam/protocols/static_solve.hpp"

namespace unjam {
namespace {

using testing::Disk;
using testing::Floor;

// Force errors are bounded by the condition number of the Delassus operator times the
// residual; a stack of k disks has a condition number ~k², so solve to 1e-13 to check the
// forces to 1e-9 relative.
constexpr double kTol = 1e-13;

StaticSolveOptions Tight(const std::string& backend = "nsgs") {
  StaticSolveOptions o;
  o.backend = backend;
  o.solver.tolerance = kTol;
  o.solver.nsgs.order = SweepOrder::kSymmetric;
  return o;
}

double NormalForceBetween(const StaticSolution& s, int i, int j) {
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    if (s.contacts[k].i == i && s.contacts[k].j == j) return s.forces[k][0];
  }
  ADD_FAILURE() << "no contact " << i << "-" << j;
  return NAN;
}

// A backend's round-off below zero is stored as no normal force: a file never holds a
// pulling contact (the reader refuses one).
TEST(StaticSolve, StoredNormalForcesNeverPull) {
  StaticSolution s;
  s.contacts.resize(3);
  for (int k = 0; k < 3; ++k) {
    s.contacts[k].i = k;
    s.contacts[k].j = k + 1;
  }
  s.forces = {Eigen::Vector2d(-6e-13, 0.0), Eigen::Vector2d(-1e-23, 1e-30),
              Eigen::Vector2d(1.5, -0.2)};
  const std::vector<ContactForce> stored = ToContactForces(s);
  ASSERT_EQ(stored.size(), 2u);
  EXPECT_EQ(stored[0].i, 1);
  EXPECT_EQ(stored[0].normal, 0.0);
  EXPECT_EQ(stored[0].tangential, 1e-30);
  EXPECT_EQ(stored[1].normal, 1.5);
  EXPECT_EQ(stored[1].tangential, -0.2);
}

TEST(StaticSolve, DiskOnAFixedDiskCarriesItsWeight) {
  for (double mu : {0.0, 0.5}) {
    Scene s;
    s.cell.size = Vec2(10, 10);
    s.effects.gravity = Vec2(0.0, -2.0);
    s.effects.friction = mu;
    s.particles = {Disk(0.0, 0.0, 1.0, /*fixed=*/true), Disk(0.0, 1.7, 0.7)};
    const StaticSolution sol = SolveStatic(s, Tight());
    ASSERT_TRUE(sol.report.converged()) << sol.report.message;
    EXPECT_NEAR(NormalForceBetween(sol, 0, 1), 2.0 * s.particles[1].Mass(), 1e-9);
    EXPECT_LT(sol.equilibrium.residual, 1e-9);
    EXPECT_LT(sol.max_speed, 1e-12);
  }
}

TEST(StaticSolve, DiskOnAWallCarriesItsWeight) {
  Scene s;
  s.cell.size = Vec2(10, 10);
  s.cell.walls.push_back(Floor(0.0));
  s.effects.gravity = Vec2(0.0, -1.0);
  s.particles = {Disk(3.0, 0.6, 0.6)};
  const StaticSolution sol = SolveStatic(s, Tight());
  ASSERT_TRUE(sol.report.converged());
  ASSERT_EQ(sol.contacts.size(), 1u);
  EXPECT_TRUE(sol.contacts[0].WithWall());
  EXPECT_NEAR(sol.forces[0][0], s.particles[0].Mass(), 1e-12);
}

TEST(StaticSolve, VerticalStackCarriesCumulativeWeights) {
  const int k = 8;
  for (double mu : {0.0, 0.3}) {
    Scene s = testing::Stack(k, 0.5, 1.0, mu);
    const StaticSolution sol = SolveStatic(s, Tight());
    ASSERT_TRUE(sol.report.converged()) << sol.report.message;
    const double w = s.particles[0].Mass();
    // Contact between disk i and i+1 carries the weight of the k−1−i disks above.
    for (int i = 0; i + 1 < k; ++i)
      EXPECT_NEAR(NormalForceBetween(sol, i, i + 1), w * (k - 1 - i), 1e-9 * k * w);
    EXPECT_NEAR(NormalForceBetween(sol, 0, WallIndexToJ(0)), w * k, 1e-9 * k * w);
    EXPECT_LT(sol.equilibrium.residual, 1e-8);
  }
}

// A few sweeps leave a stack's forces far from converged. Solved on their contact pattern
// (every contact sticking) they become exact; with the polish limited to answers within
// a factor of the tolerance, the backend's own answer stays, reported as not converged.
TEST(StaticSolve, PolishReachLimitsThePatternSolve) {
  const int k = 8;
  const Scene s = testing::Stack(k, 0.5, 1.0, 0.3);
  StaticSolveOptions o = Tight();
  o.solver.SetIterationLimit(20);
  const StaticSolution polished = SolveStatic(s, o);
  ASSERT_TRUE(polished.report.converged()) << polished.report.message;
  const double w = s.particles[0].Mass();
  EXPECT_NEAR(NormalForceBetween(polished, 0, 1), w * (k - 1), 1e-9 * k * w);
  o.polish_reach = 10.0;
  const StaticSolution raw = SolveStatic(s, o);
  EXPECT_FALSE(raw.report.converged());
  EXPECT_GT(raw.report.residual, o.polish_reach * kTol);
}

TEST(StaticSolve, FrictionlessTriangularLatticeUnderPressureObeysTheVirial) {
  const double r = 0.5;
  const double pressure = 3.0;
  Scene s = testing::TriangularLattice(6, 6, r);
  s.effects.pressure_bath = PressureBath{pressure, 10.0, 0.0};
  const StaticSolution sol = SolveStatic(s, Tight());
  ASSERT_TRUE(sol.report.converged()) << sol.report.message;
  ASSERT_EQ(sol.contacts.size(), 3u * s.particles.size());
  double mean = 0.0;
  for (const auto& f : sol.forces) mean += f[0] / sol.forces.size();
  // Hyperstatic: single forces are not unique, the mean is fixed by the virial.
  EXPECT_NEAR(mean, 2.0 * pressure * r / std::sqrt(3.0), 1e-9);
  EXPECT_NEAR(sol.equilibrium.pressure, pressure, 1e-9);
  EXPECT_LT(sol.equilibrium.residual, 1e-8);
}

}  // namespace
}  // namespace unjam
