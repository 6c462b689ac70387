// The inertia LP (problem/inertia_bound.hpp) on problems with known answers: a disk on a
// floor under gravity tilted by θ (an incline), and a disk held from above.
#include "unjam/problem/inertia_bound.hpp"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace unjam {
namespace {

constexpr double kWeight = 2.0;  // m g, with m = 1 and g = 2
constexpr double kRadius = 0.5;

// A disk (body 0, mass 1, I = m R²/2) on a fixed floor (normal +y, from the floor to the
// disk) under gravity tilted by θ, one step from rest.
ContactProblem DiskOnIncline(double theta, double mu, double dt) {
  ContactProblem p;
  p.dt = dt;
  p.frictional = mu > 0.0;
  p.inv_mass = {1.0};
  p.free_velocity = {Vec2(kWeight * std::sin(theta), -kWeight * std::cos(theta)) * dt};
  if (p.frictional) {
    p.inv_inertia = {1.0 / (0.5 * kRadius * kRadius)};
    p.free_spin = {0.0};
  }
  ProblemContact floor;
  floor.body_j = 0;
  floor.normal = Vec2(0.0, 1.0);
  floor.arm_j = kRadius;
  floor.mu = mu;
  p.contacts = {floor};
  return p;
}

// Scales: the weight for the translations, the weight times the radius for the spin.
Eigen::VectorXd Scales(const ContactProblem& p) {
  Eigen::VectorXd s = Eigen::VectorXd::Constant(p.NumDofs(), kWeight);
  if (p.frictional) s[2] = kWeight * kRadius;
  return s;
}

TEST(InertiaBound, ADiskOnALevelFloorCanRest) {
  const ContactProblem p = DiskOnIncline(0.0, 0.5, 1.0);
  const InertiaBound b = SmallestInertia(p, Scales(p));
  ASSERT_TRUE(b.decided);
  EXPECT_NEAR(b.ratio, 0.0, 1e-9);
}

TEST(InertiaBound, AFrictionlessDiskOnAnInclineFallsWithItsWholeSlope) {
  const double theta = 0.3;
  const ContactProblem p = DiskOnIncline(theta, 0.0, 1.0);
  EXPECT_NEAR(SmallestInertia(p, Scales(p)).ratio, std::sin(theta), 1e-9);
}

// Friction can hold the centre only by a torque that spins the disk: the best split leaves
// half the slope's force on each, sin θ / 2, a rolling disk. Where friction cannot even
// give that much (μ cos θ < sin θ / 2), the floor pushes harder than the weight's normal
// part, by y, to raise the friction's bound: the slope leaves sin θ − μ (cos θ + y) on the
// centre, and the best y equals it: (sin θ − μ cos θ) / (1 + μ).
TEST(InertiaBound, AFrictionalDiskOnAnInclineRollsWhateverTheFriction) {
  const double theta = 0.3;
  for (double dt : {1.0, 1e-3}) {
    const ContactProblem rough = DiskOnIncline(theta, 1.0, dt);
    EXPECT_NEAR(SmallestInertia(rough, Scales(rough)).ratio, 0.5 * std::sin(theta), 1e-9) << dt;
    const double mu = 0.1;  // μ cos θ = 0.096 < sin θ / 2 = 0.148
    const ContactProblem smooth = DiskOnIncline(theta, mu, dt);
    EXPECT_NEAR(SmallestInertia(smooth, Scales(smooth)).ratio,
                (std::sin(theta) - mu * std::cos(theta)) / (1.0 + mu), 1e-9)
        << dt;
  }
}

// A disk under a fixed ceiling (normal +y, from the disk to the ceiling), gravity down:
// a unilateral contact cannot pull, so the whole weight is left; a bilateral one holds it.
TEST(InertiaBound, OnlyABilateralContactHoldsADiskFromAbove) {
  for (ConstraintKind kind : {ConstraintKind::kUnilateral, ConstraintKind::kBilateral}) {
    ContactProblem p = DiskOnIncline(0.0, 0.0, 1.0);
    p.contacts[0].body_i = 0;
    p.contacts[0].body_j = -1;
    p.contacts[0].arm_i = kRadius;
    p.contacts[0].kind = kind;
    const double expected = kind == ConstraintKind::kUnilateral ? 1.0 : 0.0;
    EXPECT_NEAR(SmallestInertia(p, Scales(p)).ratio, expected, 1e-9);
  }
}

// Holding a contact open, continued from the unperturbed LP, is the LP of the held step.
// The smooth disk of the incline above (μ = 0.1) resting on two coincident contacts:
// unperturbed, as on one, (sin θ − μ cos θ) / (1 + μ); with either held (bilateral,
// frictionless), the held one can pull while the other pushes as hard as needed, so the
// other's friction is unbounded and only the rolling limit sin θ / 2 is left.
TEST(InertiaBound, TheContinuedLpOfAHeldContactIsTheHeldStepsLp) {
  const double theta = 0.3, mu = 0.1;
  ContactProblem p = DiskOnIncline(theta, mu, 1.0);
  p.contacts.push_back(p.contacts[0]);
  const HeldContactInertia continued(p, Scales(p));
  ASSERT_TRUE(continued.ready());
  EXPECT_NEAR(SmallestInertia(p, Scales(p)).ratio,
              (std::sin(theta) - mu * std::cos(theta)) / (1.0 + mu), 1e-9);
  for (int k : {0, 1}) {
    ContactProblem held = p;
    held.contacts[k].kind = ConstraintKind::kBilateral;
    held.contacts[k].mu = 0.0;
    const InertiaBound cold = SmallestInertia(held, Scales(held));
    const InertiaBound warm = continued.WithHeld(k);
    ASSERT_TRUE(cold.decided && warm.decided);
    EXPECT_NEAR(cold.ratio, 0.5 * std::sin(theta), 1e-9) << k;
    EXPECT_NEAR(warm.ratio, cold.ratio, 1e-9) << k;
  }
  EXPECT_THROW(continued.WithHeld(2), std::out_of_range);
}

TEST(InertiaBound, ScalesMustBePositiveOnePerDegreeOfFreedom) {
  const ContactProblem p = DiskOnIncline(0.1, 0.5, 1.0);
  EXPECT_THROW(SmallestInertia(p, Eigen::VectorXd::Ones(2)), std::invalid_argument);
  EXPECT_THROW(SmallestInertia(p, Eigen::VectorXd::Zero(3)), std::invalid_argument);
}

}  // namespace
}  // namespace unjam
