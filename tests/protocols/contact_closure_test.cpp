// Tests for src/protocols/contact_closure.cpp: gaps closed by the smallest displacement.
#include <gtest/gtest.h>

#include <cmath>

#include "test_scenes.hpp"
#include "unjam/contacts/contact.hpp"
#include "unjam/protocols/contact_closure.hpp"

namespace unjam {
namespace {

using testing::Disk;

TEST(ContactClosure, TwoFreeDisksMeetHalfWay) {
  Scene s;
  s.cell.size = Vec2(10, 10);
  const double gap = 3e-7;
  s.particles = {Disk(2.0, 2.0, 0.5), Disk(2.0 + 1.0 + gap, 2.0, 0.5)};
  const ClosureReport r = CloseContacts(s, {ContactKey{0, 1, {0, 0}}});
  ASSERT_TRUE(r.closed);
  EXPECT_LE(std::abs(MakeContact(s, 0, 1, {0, 0}).gap), 1e-13);
  // The least-norm correction moves each disk by half the gap along the normal.
  EXPECT_NEAR(s.particles[0].position.x(), 2.0 + gap / 2, 1e-15);
  EXPECT_NEAR(s.particles[1].position.x(), 3.0 + gap / 2, 1e-15);
  EXPECT_DOUBLE_EQ(s.particles[0].position.y(), 2.0);
  EXPECT_NEAR(r.max_displacement, gap / 2, 1e-15);
}

TEST(ContactClosure, FixedDisksAndWallsStayPutAndOverlapsOpen) {
  Scene s;
  s.cell.size = Vec2(10, 10);
  s.cell.walls.push_back(testing::Floor(0.0));
  // A disk overlapping the floor by 1e-7, and one resting 2e-7 above a fixed disk.
  s.particles = {Disk(1.0, 0.5 - 1e-7, 0.5), Disk(5.0, 0.0, 1.0, true), Disk(5.0, 2.0 + 2e-7, 1.0)};
  const ClosureReport r =
      CloseContacts(s, {ContactKey{0, WallIndexToJ(0), {0, 0}}, ContactKey{1, 2, {0, 0}}});
  ASSERT_TRUE(r.closed);
  EXPECT_NEAR(s.particles[0].position.y(), 0.5, 1e-15);
  EXPECT_EQ(s.particles[1].position, Vec2(5.0, 0.0));
  EXPECT_NEAR(s.particles[2].position.y(), 2.0, 1e-15);
}

TEST(ContactClosure, ACellUnderPressureShrinksWithItsParticles) {
  // A chain across a periodic cell, each gap 1e-7: closing the loop needs the cell to
  // shrink (particles alone cannot close every gap of a ring). The pressure bath lets it.
  Scene s;
  const int n = 8;
  const double gap = 1e-7;
  s.cell.size = Vec2(n * (1.0 + gap), 5.0);
  s.cell.periodicity = Periodicity::kXY;
  s.effects.pressure_bath = PressureBath{1.0, 10.0, 0.0};
  std::vector<ContactKey> keys;
  for (int i = 0; i < n; ++i) {
    s.particles.push_back(Disk(0.25 + i * (1.0 + gap), 2.5, 0.5));
    if (i + 1 < n) keys.push_back({i, i + 1, {0, 0}});
  }
  keys.push_back({0, n - 1, {-1, 0}});  // across the boundary
  const ClosureReport r = CloseContacts(s, keys);
  ASSERT_TRUE(r.closed) << r.max_gap;
  EXPECT_NEAR(s.cell.size.x(), static_cast<double>(n), 1e-12);
  for (const ContactKey& k : keys)
    EXPECT_LE(std::abs(MakeContact(s, k.i, k.j, k.image).gap), 1e-13);
}

}  // namespace
}  // namespace unjam
