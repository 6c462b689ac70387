// Tests for src/io/particle_export.cpp
#include "unjam/io/particle_export.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "temp_dir_test.hpp"
#include "test_scenes.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {
namespace {

namespace fs = std::filesystem;
using testing::Disk;

class ParticleExport : public testing::TempDirTest {
 protected:
  ParticleExport() : TempDirTest("unjam_export_") {}

  static std::vector<std::string> Lines(const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }

  // The index of the first line equal to `text`, or -1.
  static int Find(const std::vector<std::string>& lines, const std::string& text) {
    const auto it = std::find(lines.begin(), lines.end(), text);
    return it == lines.end() ? -1 : static_cast<int>(it - lines.begin());
  }

  // Three disks in a periodic 10 × 10 cell: 0 touches 1 across x = 0 (1 at image −1) and
  // touches the fixed disk 2 directly.
  static Scene ThreeDisks() {
    Scene scene;
    scene.cell.size = Vec2(10.0, 10.0);
    scene.cell.periodicity = Periodicity::kXY;
    scene.particles = {Disk(0.5, 5.0, 0.5), Disk(9.5, 5.0, 0.5), Disk(1.5, 5.0, 0.5, true)};
    return scene;
  }

  static ParticleField ThreeDisksField() {
    ParticleField field;
    field.displacement = {Vec2(0.25, -0.5), Vec2(0.0, 0.0), Vec2(1.0, 2.0)};
    field.forces = {ContactForce{0, 1, {-1, 0}, 2.0, 0.125},
                    ContactForce{0, 2, {0, 0}, 1.5, -0.25}};
    field.force_change = {ContactForce{0, 2, {0, 0}, 0.75, 0.0},
                          ContactForce{1, 2, {0, 0}, 9.0, 0.0}};
    return field;
  }
};

TEST_F(ParticleExport, VtkHoldsPointsLinesAndData) {
  const fs::path path = dir_ / "particles.vtk";
  WriteVtk(ThreeDisks(), ThreeDisksField(), path);
  const std::vector<std::string> lines = Lines(path);
  ASSERT_GE(lines.size(), 4u);
  EXPECT_EQ(lines[0], "# vtk DataFile Version 3.0");
  EXPECT_EQ(lines[2], "ASCII");
  EXPECT_EQ(lines[3], "DATASET POLYDATA");

  const int points = Find(lines, "POINTS 5 double");  // 3 centres + 2 line ends
  ASSERT_GE(points, 0);
  EXPECT_EQ(lines[points + 1], "0.5 5 0");
  EXPECT_EQ(lines[points + 3], "1.5 5 0");
  EXPECT_EQ(lines[points + 4], "-0.5 5 0");  // x_1 − Lx: the line across the boundary is whole
  EXPECT_EQ(lines[points + 5], "1.5 5 0");

  const int vertices = Find(lines, "VERTICES 3 6");
  ASSERT_GE(vertices, 0);
  EXPECT_EQ(lines[vertices + 3], "1 2");
  const int segments = Find(lines, "LINES 2 6");
  ASSERT_GE(segments, 0);
  EXPECT_EQ(lines[segments + 1], "2 0 3");
  EXPECT_EQ(lines[segments + 2], "2 0 4");

  EXPECT_GE(Find(lines, "POINT_DATA 5"), 0);
  const int fixed = Find(lines, "SCALARS fixed int 1");
  ASSERT_GE(fixed, 0);
  EXPECT_EQ(lines[fixed + 2], "0");
  EXPECT_EQ(lines[fixed + 4], "1");  // disk 2
  const int displacement = Find(lines, "VECTORS displacement double");
  ASSERT_GE(displacement, 0);
  EXPECT_EQ(lines[displacement + 1], "0.25 -0.5 0");
  EXPECT_EQ(lines[displacement + 5], "0 0 0");  // a line end

  EXPECT_GE(Find(lines, "CELL_DATA 5"), 0);
  const int normal = Find(lines, "SCALARS normal_force double 1");
  ASSERT_GE(normal, 0);
  EXPECT_EQ(lines[normal + 2], "0");  // a vertex
  EXPECT_EQ(lines[normal + 5], "2");
  EXPECT_EQ(lines[normal + 6], "1.5");
  const int tangential = Find(lines, "SCALARS tangential_force double 1");
  ASSERT_GE(tangential, 0);
  EXPECT_EQ(lines[tangential + 5], "0.125");
  const int change = Find(lines, "SCALARS force_change double 1");
  ASSERT_GE(change, 0);
  EXPECT_EQ(lines[change + 5], "0");     // contact (0, 1) has no change
  EXPECT_EQ(lines[change + 6], "0.75");  // matched by key (0, 2)

  // Header 4; points 1+5; vertices 1+3; lines 1+2; point data 1 + (2+5) + (2+5) + (1+5);
  // cell data 1 + 3·(2+5).
  EXPECT_EQ(lines.size(), 60u);
}

TEST_F(ParticleExport, VtkWallLineEndsAtTheContactPoint) {
  Scene scene = testing::Stack(1, 0.5, 1.0, 0.0);
  scene.particles[0].position = Vec2(2.0, 0.5);
  ParticleField field;
  field.forces = {ContactForce{0, WallIndexToJ(0), {0, 0}, 3.0, 0.0}};
  const fs::path path = dir_ / "wall.vtk";
  WriteVtk(scene, field, path);
  const std::vector<std::string> lines = Lines(path);
  const int points = Find(lines, "POINTS 2 double");
  ASSERT_GE(points, 0);
  EXPECT_EQ(lines[points + 2], "2 0 0");
  EXPECT_GE(Find(lines, "2 0 1"), 0);
}

TEST_F(ParticleExport, EmptyFieldWritesZeroDisplacementsAndNoLines) {
  const fs::path path = dir_ / "bare.vtk";
  WriteVtk(ThreeDisks(), ParticleField{}, path);
  const std::vector<std::string> lines = Lines(path);
  EXPECT_GE(Find(lines, "POINTS 3 double"), 0);
  EXPECT_EQ(Find(lines, "LINES 0 0"), -1);
  const int displacement = Find(lines, "VECTORS displacement double");
  ASSERT_GE(displacement, 0);
  EXPECT_EQ(lines[displacement + 1], "0 0 0");
}

TEST_F(ParticleExport, ExtendedXyzHeaderAndRows) {
  const fs::path path = dir_ / "particles.xyz";
  WriteExtendedXyz(ThreeDisks(), ThreeDisksField(), path);
  const std::vector<std::string> lines = Lines(path);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0], "3");
  EXPECT_EQ(lines[1],
            "Lattice=\"10 0 0 0 10 0 0 0 1\" "
            "Properties=id:I:1:pos:R:3:radius:R:1:fixed:I:1:displacement:R:3 pbc=\"T T F\"");
  EXPECT_EQ(lines[2], "0 0.5 5 0 0.5 0 0.25 -0.5 0");
  EXPECT_EQ(lines[4], "2 1.5 5 0 0.5 1 1 2 0");
}

TEST_F(ParticleExport, ExtendedXyzPbcFollowsThePeriodicity) {
  Scene scene = ThreeDisks();
  scene.cell.periodicity = Periodicity::kX;
  scene.cell.size = Vec2(10.0, 2.5);
  const fs::path path = dir_ / "pile.xyz";
  WriteExtendedXyz(scene, ParticleField{}, path);
  const std::vector<std::string> lines = Lines(path);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_NE(lines[1].find("Lattice=\"10 0 0 0 2.5 0 0 0 1\""), std::string::npos) << lines[1];
  EXPECT_NE(lines[1].find("pbc=\"T F F\""), std::string::npos) << lines[1];
  EXPECT_EQ(lines[3], "1 9.5 5 0 0.5 0 0 0 0");
}

TEST_F(ParticleExport, MissingDirectoryThrowsAndLeavesNoFile) {
  const fs::path vtk = dir_ / "missing" / "particles.vtk";
  const fs::path xyz = dir_ / "missing" / "particles.xyz";
  EXPECT_THROW(WriteVtk(ThreeDisks(), ThreeDisksField(), vtk), OutputError);
  EXPECT_THROW(WriteExtendedXyz(ThreeDisks(), ThreeDisksField(), xyz), OutputError);
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(ParticleExport, InconsistentFieldThrowsBeforeWriting) {
  const fs::path path = dir_ / "bad.vtk";
  ParticleField short_displacement = ThreeDisksField();
  short_displacement.displacement.pop_back();
  EXPECT_THROW(WriteVtk(ThreeDisks(), short_displacement, path), std::invalid_argument);
  ParticleField bad_index = ThreeDisksField();
  bad_index.forces.push_back(ContactForce{0, 7, {0, 0}, 1.0, 0.0});
  EXPECT_THROW(WriteVtk(ThreeDisks(), bad_index, path), std::invalid_argument);
  ParticleField bad_wall = ThreeDisksField();
  bad_wall.forces.push_back(ContactForce{0, WallIndexToJ(0), {0, 0}, 1.0, 0.0});  // no walls
  EXPECT_THROW(WriteExtendedXyz(ThreeDisks(), bad_wall, path), std::invalid_argument);
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace unjam
