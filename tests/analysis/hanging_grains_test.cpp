// Tests for HangingGrains (src/analysis/hanging_grains.cpp): a grain whose every contact
// lies above its centre can fall freely; one resting on a neighbour below cannot.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "unjam/analysis/hanging_grains.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {
namespace {

Particle Disk(double x, double y, double r, bool fixed = false) {
  Particle p;
  p.position = Vec2(x, y);
  p.radius = r;
  p.fixed = fixed;
  return p;
}

// Two fixed unit disks 2 apart; a disk of radius 0.5 touches both at distance 1.5 from
// their centres, at height 1 ∓ √1.25: below them it hangs (both contacts above its
// centre), above them it rests. A third free disk touches nothing.
TEST(HangingGrains, AGrainWedgedFromAboveHangsAndOneRestingBelowDoesNot) {
  Scene scene;
  scene.cell.size = Vec2(40.0, 40.0);
  scene.effects.gravity = Vec2(0.0, -1.0);
  const double drop = std::sqrt(1.25);
  scene.particles = {Disk(9.0, 10.0, 1.0, true),   Disk(11.0, 10.0, 1.0, true),
                     Disk(10.0, 10.0 - drop, 0.5), Disk(19.0, 10.0, 1.0, true),
                     Disk(21.0, 10.0, 1.0, true),  Disk(20.0, 10.0 + drop, 0.5),
                     Disk(30.0, 30.0, 0.5)};
  const std::vector<Contact> contacts = DetectContacts(scene, 1e-9);
  ASSERT_EQ(contacts.size(), 4u);
  EXPECT_EQ(HangingGrains(scene, contacts), std::vector<int>({2}));

  // Turned upside down, the two swap roles.
  scene.effects.gravity = Vec2(0.0, 1.0);
  EXPECT_EQ(HangingGrains(scene, contacts), std::vector<int>({5}));
  // Without gravity nothing hangs.
  scene.effects.gravity.reset();
  EXPECT_TRUE(HangingGrains(scene, contacts).empty());
}

// The bundled μ = 1 pile 25 wide has one such grain, 206 (docs/perturbations.md, "At
// μ = 1"), and the μ = 0.1 pile none: friction 0.1 holds no grain from above.
TEST(HangingGrains, TheBundledPiles) {
  const std::string dir = std::string(UNJAM_SOURCE_DIR) + "/problems/";
  const Scene mu1 = ReadPacking(dir + "gravity-n400-w25-mu1.unjam");
  EXPECT_EQ(HangingGrains(mu1, DetectContacts(mu1, 1e-9)), std::vector<int>({206}));
  const Scene mu01 = ReadPacking(dir + "gravity-n1600-mu0.1.unjam");
  EXPECT_TRUE(HangingGrains(mu01, DetectContacts(mu01, 1e-9)).empty());
}

}  // namespace
}  // namespace unjam
