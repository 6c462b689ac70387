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

}  // namespace
}  // namespace unjam
