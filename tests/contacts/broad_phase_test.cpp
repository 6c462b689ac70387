// Tests for src/contacts/broad_phase.cpp
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "test_scenes.hpp"
#include "unjam/contacts/contact.hpp"

namespace unjam {
namespace {

struct SceneSpec {
  int n = 200;
  double packing = 0.8;
  double aspect = 1.0;  // Lx / Ly
  Periodicity periodicity = Periodicity::kNone;
  bool walls = false;
  bool fixed = false;  // make every fifth particle fixed
  std::uint64_t seed = 1;
};

std::string Describe(const SceneSpec& s, double margin) {
  return "n=" + std::to_string(s.n) + " phi=" + std::to_string(s.packing) +
         " aspect=" + std::to_string(s.aspect) +
         " periodicity=" + std::to_string(static_cast<int>(s.periodicity)) +
         " walls=" + std::to_string(s.walls) + " fixed=" + std::to_string(s.fixed) +
         " seed=" + std::to_string(s.seed) + " margin=" + std::to_string(margin);
}

// Uniformly random (hence overlapping) polydisperse disks, radii uniform in [0.5, 1], with
// a few placed exactly on the lower cell edges and on the last double below the upper ones.
Scene RandomScene(const SceneSpec& spec) {
  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> radius(0.5, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Scene scene;
  scene.cell.periodicity = spec.periodicity;
  double area = 0.0;
  for (int i = 0; i < spec.n; ++i) {
    Particle p;
    p.radius = radius(rng);
    p.fixed = spec.fixed && i % 5 == 2;
    area += std::numbers::pi * p.radius * p.radius;
    scene.particles.push_back(p);
  }
  const double box = area / spec.packing;
  // Keep periodic lengths legal (≥ 2 (2 R_max + margin) with margin ≤ 0.3).
  const double lx = std::max(std::sqrt(box * spec.aspect), 4.7);
  const double ly = std::max(box / lx, 4.7);
  scene.cell.size = Vec2(lx, ly);
  for (Particle& p : scene.particles) p.position = Vec2(lx * unit(rng), ly * unit(rng));
  const double top_x = std::nextafter(lx, 0.0);
  const double top_y = std::nextafter(ly, 0.0);
  const Vec2 edges[] = {{0.0, 0.3 * ly}, {top_x, 0.3 * ly}, {0.5 * lx, 0.0}, {0.5 * lx, top_y},
                        {0.0, 0.0},      {top_x, top_y},    {0.0, top_y},    {top_x, 0.0}};
  for (int k = 0; k < 8 && k < spec.n; ++k) scene.particles[3 * k % spec.n].position = edges[k];
  if (spec.walls) {
    scene.cell.walls.push_back({Vec2(0.0, 0.0), Vec2(0.0, 1.0)});
    scene.cell.walls.push_back({Vec2(0.0, ly), Vec2(0.0, -1.0)});
    scene.cell.walls.push_back({Vec2(0.0, 0.0), Vec2(1.0, 0.0)});
    scene.cell.walls.push_back({Vec2(lx, 0.3 * ly), Vec2(-0.6, 0.8)});  // inclined
  }
  return scene;
}

std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x); }

void ExpectSameBits(const Vec2& a, const Vec2& b, const char* what, std::size_t k) {
  EXPECT_EQ(Bits(a.x()), Bits(b.x())) << what << " x of contact " << k;
  EXPECT_EQ(Bits(a.y()), Bits(b.y())) << what << " y of contact " << k;
}

// The cell list must reproduce the reference exactly: same contacts, order and bits.
void ExpectMatchesBruteForce(const Scene& scene, double margin, const std::string& label) {
  SCOPED_TRACE(label);
  const std::vector<Contact> fast = DetectContacts(scene, margin);
  const std::vector<Contact> slow = DetectContactsBruteForce(scene, margin);
  ASSERT_EQ(fast.size(), slow.size());
  for (std::size_t k = 0; k < fast.size(); ++k) {
    const Contact& a = fast[k];
    const Contact& b = slow[k];
    ASSERT_EQ(a.i, b.i) << "contact " << k;
    ASSERT_EQ(a.j, b.j) << "contact " << k;
    ASSERT_EQ(a.image, b.image) << "contact " << k;
    EXPECT_EQ(Bits(a.gap), Bits(b.gap)) << "gap of contact " << k;
    ExpectSameBits(a.normal, b.normal, "normal", k);
    ExpectSameBits(a.branch_i, b.branch_i, "branch_i", k);
    ExpectSameBits(a.branch_j, b.branch_j, "branch_j", k);
    ExpectSameBits(a.center_to_center, b.center_to_center, "center_to_center", k);
  }
}

TEST(BroadPhase, MatchesBruteForceOnRandomScenes) {
  std::uint64_t seed = 100;
  std::size_t total = 0;
  for (Periodicity periodicity : {Periodicity::kNone, Periodicity::kX, Periodicity::kXY}) {
    for (double packing : {0.1, 0.8, 1.6}) {
      for (double aspect : {1.0, 5.0, 0.2}) {
        for (bool extras : {false, true}) {
          SceneSpec spec{.n = 250,
                         .packing = packing,
                         .aspect = aspect,
                         .periodicity = periodicity,
                         .walls = extras,
                         .fixed = extras,
                         .seed = ++seed};
          const Scene scene = RandomScene(spec);
          for (double margin : {0.0, 1e-9, 0.3}) {
            ExpectMatchesBruteForce(scene, margin, Describe(spec, margin));
            total += DetectContacts(scene, margin).size();
          }
        }
      }
    }
  }
  EXPECT_GT(total, 10000u);  // the comparison is not vacuous
}

TEST(BroadPhase, MatchesBruteForceForSmallAndLargeCounts) {
  for (int n : {0, 1, 2, 3, 7, 1000}) {
    for (Periodicity periodicity : {Periodicity::kNone, Periodicity::kXY}) {
      SceneSpec spec{.n = n,
                     .packing = 0.9,
                     .periodicity = periodicity,
                     .walls = true,
                     .fixed = true,
                     .seed = static_cast<std::uint64_t>(n) + 7};
      ExpectMatchesBruteForce(RandomScene(spec), 1e-9, Describe(spec, 1e-9));
    }
  }
}

// Contacts come sorted by key, so a contact is found by binary search (FindContact).
TEST(BroadPhase, EveryContactIsFoundByItsKey) {
  const Scene s = testing::TriangularLattice(6, 6, 0.5);
  const std::vector<Contact> contacts = DetectContacts(s, 1e-6);
  ASSERT_FALSE(contacts.empty());
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    EXPECT_EQ(FindContact(contacts, contacts[k].i, contacts[k].j, contacts[k].image),
              static_cast<int>(k));
  }
  EXPECT_EQ(FindContact(contacts, contacts[0].i, contacts[0].j, {7, 7}), -1);
}

TEST(BroadPhase, SingleParticleSeesOnlyWalls) {
  SceneSpec spec{.n = 1, .walls = true};
  Scene scene = RandomScene(spec);
  scene.particles[0].position = Vec2(0.5, 0.5);
  const std::vector<Contact> contacts = DetectContacts(scene, 0.0);
  ASSERT_EQ(contacts.size(), 2u);  // floor and left wall
  EXPECT_TRUE(contacts[0].WithWall());
  EXPECT_TRUE(contacts[1].WithWall());
  EXPECT_TRUE(DetectContacts(Scene{}, 0.0).empty());
}

// Positions at the very edges of the periodic cell, where the image offsets change.
TEST(BroadPhase, ParticlesOnTheCellEdges) {
  Scene scene;
  scene.cell.size = Vec2(12.0, 9.0);
  scene.cell.periodicity = Periodicity::kXY;
  const double xs[] = {0.0, std::nextafter(0.0, 1.0), 1.9, 6.0, 10.1, std::nextafter(12.0, 0.0)};
  const double ys[] = {0.0, 1.5, 4.5, 7.5, std::nextafter(9.0, 0.0)};
  int k = 0;
  for (double x : xs) {
    for (double y : ys) {
      Particle p;
      p.position = Vec2(x, y);
      p.radius = 0.5 + 0.5 * (k++ % 3) / 2.0;
      scene.particles.push_back(p);
    }
  }
  for (double margin : {0.0, 1e-9, 0.3}) ExpectMatchesBruteForce(scene, margin, "edges");
  scene.cell.periodicity = Periodicity::kX;
  for (double margin : {0.0, 1e-9, 0.3}) ExpectMatchesBruteForce(scene, margin, "edges x");
}

// Callers are expected to wrap, but positions a little outside [0, L) must still give the
// reference's contacts (binning wraps, the geometry uses the stored positions).
TEST(BroadPhase, PositionsSlightlyOutsideTheCell) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    SceneSpec spec{
        .n = 300, .packing = 0.8, .aspect = 2.0, .periodicity = Periodicity::kXY, .seed = seed};
    Scene scene = RandomScene(spec);
    const Vec2 size = scene.cell.size;
    const double offsets[] = {-1e-12, 1e-12, -0.4, 0.4, -1e-300};
    for (int k = 0; k < 60; ++k) {
      Vec2& x = scene.particles[5 * k].position;
      const double d = offsets[k % 5];
      if (k % 2 == 0) x.x() = d < 0 ? d : size.x() + d;
      if (k % 3 == 0) x.y() = d < 0 ? d : size.y() + d;
    }
    for (double margin : {0.0, 1e-9, 0.3}) ExpectMatchesBruteForce(scene, margin, "outside");
  }
}

// Periodic lengths right at the legal minimum leave one or two cells per axis, where the
// neighbours on both sides are the same cell through different images.
TEST(BroadPhase, OneOrTwoCellsAlongPeriodicAxes) {
  for (double factor : {1.0, 1.3, 2.0, 2.5, 3.1}) {
    for (double margin : {0.0, 0.3}) {
      SceneSpec spec{.n = 40, .packing = 1.2, .periodicity = Periodicity::kXY, .seed = 9};
      Scene scene = RandomScene(spec);
      const double minimum = 2.0 * (2.0 * MaxRadius(scene) + margin);
      scene.cell.size = Vec2(factor * minimum, minimum);
      std::mt19937_64 rng(11);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      for (Particle& p : scene.particles) {
        p.position = Vec2(scene.cell.size.x() * unit(rng), scene.cell.size.y() * unit(rng));
      }
      ExpectMatchesBruteForce(scene, margin, "factor " + std::to_string(factor));
    }
  }
}

// Every contact sits exactly at the reach 2 R_max + margin of the grid, the case a cell a
// little too narrow would miss.
TEST(BroadPhase, SquareLatticeAtTheReach) {
  for (int k : {3, 4, 7, 60}) {  // 60: a 2 % too narrow cell would already fail
    for (double margin : {0.0, 1e-9, 0.3}) {
      Scene scene;
      const double spacing = 2.0 + margin;
      scene.cell.size = Vec2(k * spacing, 5 * spacing);
      scene.cell.periodicity = Periodicity::kXY;
      for (int a = 0; a < k; ++a) {
        for (int b = 0; b < 5; ++b) {
          Particle p;
          p.position = Vec2(a * spacing, b * spacing);
          scene.particles.push_back(p);
        }
      }
      ExpectMatchesBruteForce(scene, std::nextafter(margin, 1.0), "lattice");
      // Gaps round to about ±1e-16 around the margin: all 2 N bonds, or very nearly.
      const std::size_t n = scene.particles.size();
      EXPECT_GE(DetectContacts(scene, std::nextafter(margin, 1.0) + 1e-12).size(), 2 * n);
    }
  }
}

TEST(BroadPhase, AllParticlesInOneCell) {
  Scene scene;
  scene.cell.size = Vec2(100.0, 100.0);
  scene.cell.walls.push_back({Vec2(0.0, 50.0), Vec2(0.0, 1.0)});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 50; ++i) {
    Particle p;
    p.radius = 0.5 + 0.5 * unit(rng);
    p.position = Vec2(50.0 + 0.5 * unit(rng), 50.0 + 0.5 * unit(rng));
    scene.particles.push_back(p);
  }
  scene.particles[3].position = scene.particles[4].position;  // coincident centres
  ExpectMatchesBruteForce(scene, 0.0, "one cell");
  EXPECT_EQ(DetectContacts(scene, 0.0).size(), 50u * 49u / 2u + 50u);
}

// Few particles in an enormous domain: the grid must be capped, not sized by area.
TEST(BroadPhase, HugeSparseDomain) {
  for (Periodicity periodicity : {Periodicity::kNone, Periodicity::kXY}) {
    Scene scene;
    scene.cell.size = Vec2(1e9, 3e8);
    scene.cell.periodicity = periodicity;
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 200; ++i) {
      Particle p;
      p.radius = 0.5 + 0.5 * unit(rng);
      p.position = Vec2(1e9 * unit(rng), 3e8 * unit(rng));
      if (i % 2 == 1) p.position = scene.particles.back().position + Vec2(0.9, 0.3);  // touching
      scene.particles.push_back(p);
    }
    ExpectMatchesBruteForce(scene, 1e-9, "sparse");
    EXPECT_GE(DetectContacts(scene, 1e-9).size(), 100u);
  }
}

TEST(BroadPhase, TouchingAcrossThePeriodicBoundary) {
  Scene scene;
  scene.cell.size = Vec2(10.0, 8.0);
  scene.cell.periodicity = Periodicity::kX;
  Particle a;
  a.radius = 0.75;
  a.position = Vec2(9.75, 3.0);
  Particle b;
  b.radius = 0.625;
  b.position = Vec2(1.125, 3.0);  // 9.75 + 0.75 + 0.625 − 10
  scene.particles = {a, b};
  std::vector<Contact> contacts = DetectContacts(scene, 1e-9);
  ASSERT_EQ(contacts.size(), 1u);
  Contact c = contacts[0];
  EXPECT_EQ(c.i, 0);
  EXPECT_EQ(c.j, 1);
  EXPECT_EQ(c.image, (std::array<int, 2>{1, 0}));
  EXPECT_NEAR(c.gap, 0.0, 1e-15);
  EXPECT_NEAR(c.normal.x(), 1.0, 1e-15);  // from i at the right edge across to j
  EXPECT_NEAR(c.normal.y(), 0.0, 1e-15);
  EXPECT_NEAR(c.center_to_center.norm(), 1.375, 1e-15);

  std::swap(scene.particles[0], scene.particles[1]);  // now i is near x = 0
  contacts = DetectContacts(scene, 1e-9);
  ASSERT_EQ(contacts.size(), 1u);
  c = contacts[0];
  EXPECT_EQ(c.image, (std::array<int, 2>{-1, 0}));
  EXPECT_NEAR(c.gap, 0.0, 1e-15);
  EXPECT_NEAR(c.normal.x(), -1.0, 1e-15);
  EXPECT_NEAR(c.center_to_center.norm(), 1.375, 1e-15);
}

TEST(BroadPhase, TouchingAcrossTheCorner) {
  Scene scene;
  scene.cell.size = Vec2(10.0, 10.0);
  scene.cell.periodicity = Periodicity::kXY;
  Particle p;
  p.radius = 0.5;
  const double d = std::sqrt(0.5);  // centres √2 d = 1 apart along the diagonal
  p.position = Vec2(10.0 - 0.5 * d, 10.0 - 0.5 * d);
  scene.particles.push_back(p);
  p.position = Vec2(0.5 * d, 0.5 * d);
  scene.particles.push_back(p);
  const std::vector<Contact> contacts = DetectContacts(scene, 1e-9);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].image, (std::array<int, 2>{1, 1}));
  EXPECT_NEAR(contacts[0].gap, 0.0, 1e-14);
  ExpectMatchesBruteForce(scene, 1e-9, "corner");
}

TEST(BroadPhase, FixedPairsAreSkipped) {
  Scene scene;
  scene.cell.size = Vec2(10.0, 10.0);
  scene.cell.walls.push_back({Vec2(0.0, 0.0), Vec2(0.0, 1.0)});
  Particle p;
  p.fixed = true;
  p.position = Vec2(1.0, 0.5);
  scene.particles.push_back(p);
  p.position = Vec2(2.5, 0.5);
  scene.particles.push_back(p);
  p.fixed = false;
  p.position = Vec2(1.75, 2.0);
  scene.particles.push_back(p);
  const std::vector<Contact> contacts = DetectContacts(scene, 0.0);
  // No fixed–fixed pair and no wall contact for fixed disks; the free disk touches both.
  ASSERT_EQ(contacts.size(), 2u);
  EXPECT_EQ(contacts[0].i, 0);
  EXPECT_EQ(contacts[0].j, 2);
  EXPECT_EQ(contacts[1].i, 1);
  EXPECT_EQ(contacts[1].j, 2);
  ExpectMatchesBruteForce(scene, 0.0, "fixed");
}

TEST(BroadPhase, ThrowsWhenThePeriodicCellIsTooSmall) {
  Scene scene;
  Particle p;
  scene.particles.push_back(p);
  p.position = Vec2(1.0, 1.0);
  scene.particles.push_back(p);
  scene.cell.periodicity = Periodicity::kX;
  scene.cell.size = Vec2(std::nextafter(2.0 * (2.0 + 0.3), 0.0), 1.0);  // y is not periodic
  EXPECT_THROW(DetectContacts(scene, 0.3), std::invalid_argument);
  EXPECT_THROW(DetectContactsBruteForce(scene, 0.3), std::invalid_argument);
  scene.cell.size.x() = 2.0 * (2.0 + 0.3);
  EXPECT_NO_THROW(DetectContacts(scene, 0.3));
  EXPECT_NO_THROW(DetectContactsBruteForce(scene, 0.3));
  scene.cell.periodicity = Periodicity::kXY;
  EXPECT_THROW(DetectContacts(scene, 0.3), std::invalid_argument);
  EXPECT_THROW(DetectContactsBruteForce(scene, 0.3), std::invalid_argument);
}

// The workspace is reused between calls; a shrinking then growing scene must not see
// stale data.
TEST(BroadPhase, RepeatedCallsOnDifferentScenes) {
  for (int n : {500, 20, 0, 800, 3}) {
    SceneSpec spec{.n = n, .periodicity = Periodicity::kX, .seed = static_cast<std::uint64_t>(n)};
    const Scene scene = RandomScene(spec);
    ExpectMatchesBruteForce(scene, 1e-9, Describe(spec, 1e-9));
  }
}

}  // namespace
}  // namespace unjam
