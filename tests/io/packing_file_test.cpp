// Tests for src/io/packing_file.cpp
#include "unjam/io/packing_file.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "io/random_scene.hpp"

namespace unjam {
namespace {

using testing::RandomScene;

std::uint64_t Bits(double v) { return std::bit_cast<std::uint64_t>(v); }

#define EXPECT_SAME_BITS(a, b) EXPECT_EQ(Bits(a), Bits(b)) << #a << " = " << (a) << " vs " << (b)

void ExpectSameVec(const Vec2& a, const Vec2& b) {
  EXPECT_SAME_BITS(a.x(), b.x());
  EXPECT_SAME_BITS(a.y(), b.y());
}

void ExpectSameEffects(const Effects& a, const Effects& b) {
  ASSERT_EQ(a.gravity.has_value(), b.gravity.has_value());
  if (a.gravity) ExpectSameVec(*a.gravity, *b.gravity);
  EXPECT_SAME_BITS(a.friction, b.friction);
  ASSERT_EQ(a.pressure_bath.has_value(), b.pressure_bath.has_value());
  if (a.pressure_bath) {
    EXPECT_SAME_BITS(a.pressure_bath->pressure, b.pressure_bath->pressure);
    EXPECT_SAME_BITS(a.pressure_bath->cell_mass, b.pressure_bath->cell_mass);
    EXPECT_SAME_BITS(a.pressure_bath->strain_rate, b.pressure_bath->strain_rate);
  }
  ASSERT_EQ(a.prescribed_motion.size(), b.prescribed_motion.size());
  for (std::size_t k = 0; k < a.prescribed_motion.size(); ++k) {
    EXPECT_EQ(a.prescribed_motion[k].particle, b.prescribed_motion[k].particle);
    ExpectSameVec(a.prescribed_motion[k].velocity, b.prescribed_motion[k].velocity);
    EXPECT_SAME_BITS(a.prescribed_motion[k].spin, b.prescribed_motion[k].spin);
  }
  ASSERT_EQ(a.prescribed_gaps.size(), b.prescribed_gaps.size());
  for (std::size_t k = 0; k < a.prescribed_gaps.size(); ++k) {
    EXPECT_EQ(a.prescribed_gaps[k].i, b.prescribed_gaps[k].i);
    EXPECT_EQ(a.prescribed_gaps[k].j, b.prescribed_gaps[k].j);
    EXPECT_EQ(a.prescribed_gaps[k].image, b.prescribed_gaps[k].image);
    EXPECT_SAME_BITS(a.prescribed_gaps[k].gap, b.prescribed_gaps[k].gap);
  }
}

void ExpectSameScene(const Scene& a, const Scene& b) {
  ExpectSameVec(a.cell.size, b.cell.size);
  EXPECT_EQ(a.cell.periodicity, b.cell.periodicity);
  ASSERT_EQ(a.cell.walls.size(), b.cell.walls.size());
  for (std::size_t k = 0; k < a.cell.walls.size(); ++k) {
    ExpectSameVec(a.cell.walls[k].point, b.cell.walls[k].point);
    ExpectSameVec(a.cell.walls[k].normal, b.cell.walls[k].normal);
  }
  ExpectSameEffects(a.effects, b.effects);
  ASSERT_EQ(a.particles.size(), b.particles.size());
  for (std::size_t k = 0; k < a.particles.size(); ++k) {
    const Particle& p = a.particles[k];
    const Particle& q = b.particles[k];
    ExpectSameVec(p.position, q.position);
    EXPECT_SAME_BITS(p.angle, q.angle);
    ExpectSameVec(p.velocity, q.velocity);
    EXPECT_SAME_BITS(p.spin, q.spin);
    EXPECT_SAME_BITS(p.radius, q.radius);
    EXPECT_SAME_BITS(p.density, q.density);
    EXPECT_EQ(p.fixed, q.fixed);
  }
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.provenance, b.provenance);
  ASSERT_EQ(a.forces.size(), b.forces.size());
  for (std::size_t k = 0; k < a.forces.size(); ++k) {
    EXPECT_EQ(a.forces[k].i, b.forces[k].i);
    EXPECT_EQ(a.forces[k].j, b.forces[k].j);
    EXPECT_EQ(a.forces[k].image, b.forces[k].image);
    EXPECT_SAME_BITS(a.forces[k].normal, b.forces[k].normal);
    EXPECT_SAME_BITS(a.forces[k].tangential, b.forces[k].tangential);
  }
}

TEST(PackingFile, RoundTripIsBitForBitOnRandomScenes) {
  std::mt19937_64 rng(20240601);
  for (int trial = 0; trial < 300; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const Scene scene = RandomScene(rng);
    const std::string text = FormatPacking(scene);
    Scene read;
    ASSERT_NO_THROW(read = ParsePacking(text, "random.unjam")) << text;
    ExpectSameScene(scene, read);
    EXPECT_EQ(FormatPacking(read), text);  // a second trip changes nothing either
    if (::testing::Test::HasFailure()) break;
  }
}

TEST(PackingFile, RoundTripKeepsAwkwardDoublesExactly) {
  const double values[] = {0.1 + 0.2,
                           -0.0,
                           5e-324,
                           1e-300,
                           2.2250738585072011e-308,
                           std::numeric_limits<double>::max(),
                           -1.7976931348623157e308,
                           1.0 / 3.0};
  Scene scene;
  scene.cell.size = Vec2(3.0, 3.0);
  scene.particles.resize(1);
  scene.particles[0].position = Vec2(1.5, 1.5);
  for (const double v : values) {
    scene.particles[0].angle = v;
    scene.particles[0].spin = -v;
    scene.effects.gravity = Vec2(v, v);
    const Scene read = ParsePacking(FormatPacking(scene), "awkward.unjam");
    EXPECT_SAME_BITS(read.particles[0].angle, v);
    EXPECT_SAME_BITS(read.particles[0].spin, -v);
    EXPECT_SAME_BITS(read.effects.gravity->x(), v);
  }
}

TEST(PackingFile, FormatIsReadableAndDocumented) {
  Scene scene;
  scene.cell.size = Vec2(40.0, 40.0);
  scene.cell.periodicity = Periodicity::kXY;
  scene.effects.friction = 0.5;
  scene.seed = 42;
  scene.provenance = "unjam pack --n 1 # all of it";
  Particle p;
  p.position = Vec2(0.1 + 0.2, 2.0);
  scene.particles.push_back(p);
  EXPECT_EQ(FormatPacking(scene),
            "unjam-packing 1\ncell 40 40\nperiodic xy\nfriction 0.5\nseed 42\n"
            "provenance unjam pack --n 1 # all of it\nparticles 1\n"
            "# x y angle vx vy spin radius density fixed\n"
            "0.30000000000000004 2 0 0 0 0 1 1 0\nend\n");
}

TEST(PackingFile, AcceptsCommentsCrlfBomAnyKeyOrderAndPlusSigns) {
  const std::string text =
      "\xEF\xBB\xBF# a comment before the header\r\n"
      "unjam-packing 1   # version\r\n"
      "\r\n"
      "particles 2\r\n"
      "  # the first disk\r\n"
      "+0.5\t0.5 0 0 0 0 0.5 1 0\r\n"
      "1.5 0.5 0 0 0 0 .5 1e0 1 # fixed\r\n"
      "cell 4 4\r\n"
      "periodic x\r\n"
      "provenance keeps # and \\\\ and \\x41\r\n"
      "end\r\n"
      "# trailing comment\r\n";
  const Scene scene = ParsePacking(text, "ok.unjam");
  ASSERT_EQ(scene.particles.size(), 2u);
  EXPECT_EQ(scene.particles[0].position.x(), 0.5);
  EXPECT_TRUE(scene.particles[1].fixed);
  EXPECT_EQ(scene.cell.periodicity, Periodicity::kX);
  EXPECT_EQ(scene.provenance, "keeps # and \\ and A");
  EXPECT_EQ(scene.effects.friction, 0.0);
  EXPECT_FALSE(scene.effects.gravity.has_value());
}

TEST(PackingFile, OverlapToleranceIsAnOption) {
  // Two disks of radius 0.5 whose centres are 1 − 1e-7 apart: overlap 1e-7.
  const std::string text =
      "unjam-packing 1\ncell 4 4\nparticles 2\n1 1 0 0 0 0 0.5 1 0\n1.9999999 1 0 0 0 0 0.5 1 "
      "0\nend\n";
  EXPECT_NO_THROW(ParsePacking(text, "t.unjam"));
  ReadOptions strict;
  strict.overlap_tolerance = 1e-9;
  EXPECT_THROW(ParsePacking(text, "t.unjam", strict), InputError);
}

TEST(PackingFile, FixedDisksMayTouchEachOther) {
  const std::string text =
      "unjam-packing 1\ncell 4 4\nparticles 2\n1 1 0 0 0 0 0.5 1 1\n1.5 1 0 0 0 0 0.5 1 1\nend\n";
  EXPECT_NO_THROW(ParsePacking(text, "bed.unjam"));
}

// The fuzzer's seed corpus doubles as a set of hand-written example files.
TEST(PackingFile, SeedCorpusFilesAreValid) {
  const std::filesystem::path dir =
      std::filesystem::path(UNJAM_SOURCE_DIR) / "tests" / "fuzz" / "corpus";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    SCOPED_TRACE(entry.path().string());
    const Scene scene = ReadPacking(entry.path());
    EXPECT_EQ(ParsePacking(FormatPacking(scene), "again").particles.size(), scene.particles.size());
    ++files;
  }
  EXPECT_GE(files, 3);
}

// The example in docs/format.md must stay a valid file.
TEST(PackingFile, DocumentedExampleIsValid) {
  std::ifstream in(std::filesystem::path(UNJAM_SOURCE_DIR) / "docs" / "format.md");
  std::string line;
  while (std::getline(in, line) && line != "## Example") {
  }
  while (std::getline(in, line) && line != "```") {
  }
  std::string example;
  while (std::getline(in, line) && line != "```") example += line + "\n";
  ASSERT_FALSE(example.empty());
  const Scene scene = ParsePacking(example, "format.md");
  EXPECT_EQ(scene.particles.size(), 3u);
  EXPECT_EQ(scene.forces.size(), 2u);
  EXPECT_EQ(scene.cell.walls.size(), 1u);
}

TEST(PackingFile, InputErrorFormatsFileAndLine) {
  const InputError with_line("a.unjam", 7, "bad");
  EXPECT_STREQ(with_line.what(), "a.unjam:7: bad");
  EXPECT_EQ(with_line.line(), 7);
  EXPECT_EQ(with_line.message(), "bad");
  EXPECT_STREQ(InputError("a.unjam", 0, "cannot open").what(), "a.unjam: cannot open");
}

TEST(PackingFile, ReadPackingReportsAMissingFile) {
  try {
    ReadPacking("/nonexistent/dir/x.unjam");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 0);
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/x.unjam: cannot open"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace unjam
