// Tests for ComputeCoordination (src/analysis/equilibrium.cpp): z and rattlers count only
// contacts that carry force.
#include <gtest/gtest.h>

#include "unjam/analysis/equilibrium.hpp"

namespace unjam {
namespace {

// Three free disks in a triangle with normal forces on 0–1, 1–2 and 0–2.
Coordination OfTriangle(double f01, double f12, double f02) {
  Scene scene;
  scene.particles.resize(3);
  const std::vector<ContactForce> forces = {
      {0, 1, {0, 0}, f01, 0.0}, {1, 2, {0, 0}, f12, 0.0}, {0, 2, {0, 0}, f02, 0.0}};
  return ComputeCoordination(scene, forces);
}

// 1–2 carries a round-off 1e-18 (what a static solve leaves on a contact that carries
// nothing), 0–2 exactly zero: disk 2 is a rattler, z counts 0–1 at both of its ends.
TEST(Coordination, RoundOffForcesMakeNoBackbone) {
  const Coordination c = OfTriangle(1.0, 1e-18, 0.0);
  EXPECT_EQ(c.force_carrying_contacts, 1);
  EXPECT_EQ(c.rattlers, 1);
  EXPECT_DOUBLE_EQ(c.z, 1.0);
}

// A small force far above round-off (1e-6 of the mean) still carries.
TEST(Coordination, SmallRealForcesCarry) {
  const Coordination c = OfTriangle(1.0, 1e-6, 2.0);
  EXPECT_EQ(c.force_carrying_contacts, 3);
  EXPECT_EQ(c.rattlers, 0);
  EXPECT_DOUBLE_EQ(c.z, 2.0);
}

}  // namespace
}  // namespace unjam
