// The kinematic LP (problem/kinematic_admissibility.hpp) on problems with known answers.
#include "unjam/problem/kinematic_admissibility.hpp"

#include <gtest/gtest.h>

namespace unjam {
namespace {

// One disk (body 0) between two fixed walls along x: contact 0 with the left wall (normal
// from the wall to the disk, +x), contact 1 with the right wall (normal from the disk to
// the wall, +x, so u_n = −v_x there). Holding contact 0 open at speed `open` pushes the
// disk into the right wall unless that wall is `gap` away.
ContactProblem Squeezed(bool frictional, double open, double gap, double dt = 1.0) {
  ContactProblem p;
  p.dt = dt;
  p.frictional = frictional;
  p.inv_mass = {1.0};
  p.free_velocity = {Vec2::Zero()};
  if (frictional) {
    p.inv_inertia = {2.0};
    p.free_spin = {0.0};
  }
  ProblemContact left;
  left.body_j = 0;
  left.normal = Vec2(1.0, 0.0);
  left.kind = ConstraintKind::kBilateral;
  left.target_velocity = open;
  left.mu = frictional ? 0.5 : 0.0;
  ProblemContact right;
  right.body_i = 0;
  right.normal = Vec2(1.0, 0.0);
  right.bias = Vec2(gap / dt, 0.0);  // the gap closes at most by itself within the step
  right.mu = left.mu;
  p.contacts = {left, right};
  return p;
}

TEST(KinematicAdmissibility, OpeningAgainstARigidWallIsBlocked) {
  for (bool frictional : {false, true}) {
    const KinematicAdmissibility k = CheckKinematicAdmissibility(Squeezed(frictional, 1e-9, 0.0));
    EXPECT_TRUE(k.decided);
    EXPECT_FALSE(k.admissible) << "frictional " << frictional;
  }
}

TEST(KinematicAdmissibility, AGapWideEnoughLetsItOpen) {
  EXPECT_TRUE(CheckKinematicAdmissibility(Squeezed(false, 1e-9, 2e-9)).admissible);
  // A gap of half the opening is not enough; the LP sees it at the scale of the opening.
  EXPECT_FALSE(CheckKinematicAdmissibility(Squeezed(false, 1e-9, 0.5e-9)).admissible);
}

TEST(KinematicAdmissibility, NoPrescriptionIsAlwaysAdmissible) {
  EXPECT_TRUE(CheckKinematicAdmissibility(Squeezed(true, 0.0, 0.0)).admissible);
}

}  // namespace
}  // namespace unjam
