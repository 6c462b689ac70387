// Tests for src/stepping/simulation.cpp: Moreau–Jean dynamics with known answers.
#include <gtest/gtest.h>

#include <cmath>

#include "test_scenes.hpp"
#include "unjam/stepping/simulation.hpp"

namespace unjam {
namespace {

using testing::Disk;

StepOptions Options(double dt) {
  StepOptions o;
  o.dt = dt;
  o.solver.tolerance = 1e-12;
  return o;
}

// A disk of radius r on a wall inclined by θ, released from rest, under gravity g.
Scene Incline(double theta, double mu, double r, double g) {
  Scene s;
  s.cell.size = Vec2(100, 100);
  const Vec2 normal(-std::sin(theta), std::cos(theta));
  s.cell.walls.push_back(Wall{Vec2::Zero(), normal});
  s.effects.gravity = Vec2(0.0, -g);
  s.effects.friction = mu;
  s.particles.push_back(Disk(0.0, 0.0, r));
  s.particles[0].position = r * normal;
  return s;
}

struct InclineMotion {
  double acceleration;  // along the slope, downhill
  double spin_rate;     // dω/dt (negative = clockwise, rolling downhill to the left)
  double lift;          // largest distance from the wall (no bouncing, no penetration)
};

InclineMotion Roll(double theta, double mu) {
  const double r = 0.8;
  const double g = 1.0;
  const double dt = 1e-3;
  const int steps = 2000;
  Simulation sim(Incline(theta, mu, r, g), Options(dt));
  const Vec2 downhill(-std::cos(theta), -std::sin(theta));
  const Vec2 normal(-std::sin(theta), std::cos(theta));
  double lift = 0.0;
  for (int n = 0; n < steps; ++n) {
    sim.Step();
    lift = std::max(lift, std::abs(sim.scene().particles[0].position.dot(normal) - r));
  }
  const Particle& p = sim.scene().particles[0];
  return {p.velocity.dot(downhill) / (steps * dt), p.spin / (steps * dt), lift};
}

TEST(Dynamics, DiskRollsWithoutSlippingWhenFrictionSuffices) {
  const double theta = 0.3;
  const double mu = std::tan(theta) / 3.0 * 1.5;
  const InclineMotion m = Roll(theta, mu);
  EXPECT_NEAR(m.acceleration, 2.0 / 3.0 * std::sin(theta), 1e-9);
  // Rolling: v = −ω r, so dω/dt = −a / r (the disk turns anticlockwise going left).
  EXPECT_NEAR(m.spin_rate, m.acceleration / 0.8, 1e-9);
  EXPECT_LT(m.lift, 1e-9);
}

TEST(Dynamics, DiskSlipsWhenFrictionIsTooWeak) {
  const double theta = 0.5;
  const double mu = std::tan(theta) / 3.0 * 0.5;
  const InclineMotion m = Roll(theta, mu);
  EXPECT_NEAR(m.acceleration, std::sin(theta) - mu * std::cos(theta), 1e-9);
  EXPECT_NEAR(std::abs(m.spin_rate), 2.0 * mu * std::cos(theta) / 0.8, 1e-9);
  EXPECT_LT(m.lift, 1e-9);
}

TEST(Dynamics, FrictionlessDiskSlidesWithoutSpinning) {
  const double theta = 0.4;
  const InclineMotion m = Roll(theta, 0.0);
  EXPECT_NEAR(m.acceleration, std::sin(theta), 1e-9);
  EXPECT_EQ(m.spin_rate, 0.0);
}

TEST(Dynamics, DiskInAVGrooveStaysAtRest) {
  for (double mu : {0.0, 0.5}) {
    Scene s;
    s.cell.size = Vec2(10, 10);
    s.effects.gravity = Vec2(0.0, -1.0);
    s.effects.friction = mu;
    const double r = 1.0;
    const double half = 1.5;  // half the distance between the fixed disks
    s.particles = {Disk(-half, 0.0, r, true), Disk(half, 0.0, r, true),
                   Disk(0.0, std::sqrt(4.0 * r * r - half * half), r)};
    const Vec2 start = s.particles[2].position;
    Simulation sim(s, Options(1e-3));
    for (int n = 0; n < 1000; ++n) sim.Step();
    EXPECT_LT((sim.scene().particles[2].position - start).norm(), 1e-12) << "mu=" << mu;
    EXPECT_LT(sim.scene().particles[2].velocity.norm(), 1e-12);
  }
}

TEST(Dynamics, HeadOnCollisionConservesMomentumWithoutRebound) {
  Scene s;
  s.cell.size = Vec2(20, 20);
  s.particles = {Disk(5.0, 5.0, 1.0), Disk(8.0, 5.0, 0.5)};
  s.particles[0].velocity = Vec2(2.0, 0.0);
  s.particles[1].velocity = Vec2(-1.0, 0.0);
  const Vec2 momentum = s.particles[0].Mass() * s.particles[0].velocity +
                        s.particles[1].Mass() * s.particles[1].velocity;
  Simulation sim(s, Options(1e-3));
  for (int n = 0; n < 2000; ++n) sim.Step();
  const auto& p = sim.scene().particles;
  const Vec2 after = p[0].Mass() * p[0].velocity + p[1].Mass() * p[1].velocity;
  EXPECT_NEAR((after - momentum).norm(), 0.0, 1e-12);
  EXPECT_NEAR(p[0].velocity.x(), p[1].velocity.x(), 1e-12);  // perfectly inelastic
  const double gap = (p[1].position - p[0].position).norm() - 1.5;
  EXPECT_GE(gap, -1e-12);
  EXPECT_LT(gap, 1e-12);
}

TEST(Dynamics, ContactAcrossThePeriodicBoundaryStopsTheApproach) {
  Scene s;
  s.cell.size = Vec2(10, 10);
  s.cell.periodicity = Periodicity::kXY;
  s.particles = {Disk(0.7, 5.0, 0.5), Disk(9.3, 5.0, 0.5)};  // 0.4 apart across x = 0
  s.particles[0].velocity = Vec2(-1.0, 0.0);
  s.particles[1].velocity = Vec2(1.0, 0.0);
  Simulation sim(s, Options(1e-3));
  for (int n = 0; n < 500; ++n) sim.Step();
  const auto& p = sim.scene().particles;
  EXPECT_NEAR(p[0].velocity.norm(), 0.0, 1e-12);
  EXPECT_NEAR(p[1].velocity.norm(), 0.0, 1e-12);
  ASSERT_EQ(sim.contacts().size(), 1u);
  EXPECT_NE(sim.contacts()[0].image[0], 0);  // they meet on the boundary, x = 0 ≡ 10
  EXPECT_NEAR(p[0].position.x(), 0.5, 1e-12);
  EXPECT_NEAR(sim.contacts()[0].gap, 0.0, 1e-12);
}

}  // namespace
}  // namespace unjam
