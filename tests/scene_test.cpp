// Tests for src/scene/scene.cpp
#include <gtest/gtest.h>

#include "unjam/scene/scene.hpp"

namespace unjam {
namespace {

TEST(Scene, MassAndInertiaOfADisk) {
  Particle p;
  p.radius = 0.5;
  p.density = 2.0;
  EXPECT_DOUBLE_EQ(p.Mass(), 2.0 * std::numbers::pi * 0.25);
  EXPECT_DOUBLE_EQ(p.Inertia(), 0.5 * p.Mass() * 0.25);
}

TEST(Scene, WrapKeepsPositionsInsideThePeriodicCell) {
  Scene scene;
  scene.cell.size = Vec2(10.0, 5.0);
  scene.cell.periodicity = Periodicity::kX;
  Particle p;
  p.position = Vec2(-0.5, 7.0);
  scene.particles.push_back(p);
  p.position = Vec2(-1e-18, -1.0);
  scene.particles.push_back(p);
  WrapPositions(scene);
  EXPECT_DOUBLE_EQ(scene.particles[0].position.x(), 9.5);
  EXPECT_DOUBLE_EQ(scene.particles[0].position.y(), 7.0);  // y is not periodic
  EXPECT_GE(scene.particles[1].position.x(), 0.0);
  EXPECT_LT(scene.particles[1].position.x(), 10.0);
}

// Static solves leave round-off forces (1e-18 of the mean) on contacts that carry nothing;
// they must not count, or a rattler caged by such contacts counts as part of the backbone.
TEST(Scene, RoundOffForcesDoNotCarry) {
  Scene scene;
  scene.particles.resize(3);
  scene.forces.push_back({0, 1, {0, 0}, 1.0, 0.0});
  scene.forces.push_back({1, 2, {0, 0}, 1e-18, 0.0});
  scene.forces.push_back({0, 2, {0, 0}, 0.0, 0.0});
  const std::vector<ContactForce> carrying = ForceCarryingPairs(scene);
  ASSERT_EQ(carrying.size(), 1u);
  EXPECT_EQ(carrying[0].j, 1);
  EXPECT_DOUBLE_EQ(CarryingThreshold({1.0, 1e-18, 0.0}), 1e-10 * (1.0 + 1e-18) / 2.0);
  EXPECT_EQ(CarryingThreshold({0.0, -1.0}), 0.0);
}

}  // namespace
}  // namespace unjam
