// Tests for src/io/atomic_write.cpp
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "temp_dir_test.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {
namespace {

namespace fs = std::filesystem;

class AtomicWrite : public testing::TempDirTest {
 protected:
  AtomicWrite() : TempDirTest("unjam_atomic_") {}

  // Every entry of the test directory, by name.
  std::vector<std::string> Entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_))
      names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  static std::string Slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream out;
    out << in.rdbuf();
    return out.str();
  }
};

TEST_F(AtomicWrite, WritesAndReplacesLeavingNoTemporary) {
  const fs::path path = dir_ / "a.unjam";
  WriteFileAtomically(path, std::string("first\0binary", 12));
  EXPECT_EQ(Slurp(path), std::string("first\0binary", 12));
  WriteFileAtomically(path, "second");
  EXPECT_EQ(Slurp(path), "second");
  WriteFileAtomically(path, "");
  EXPECT_EQ(Slurp(path), "");
  EXPECT_EQ(Entries(), std::vector<std::string>{"a.unjam"});
}

TEST_F(AtomicWrite, MissingDirectoryThrowsNamingThePath) {
  const fs::path path = dir_ / "missing" / "a.unjam";
  try {
    WriteFileAtomically(path, "content");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(Entries(), std::vector<std::string>{});
}

TEST_F(AtomicWrite, DirectoryAtTheFinalNameThrowsAndCleansUp) {
  const fs::path path = dir_ / "taken";
  fs::create_directory(path);
  EXPECT_THROW(WriteFileAtomically(path, "content"), std::runtime_error);
  EXPECT_TRUE(fs::is_directory(path));
  EXPECT_EQ(Entries(), std::vector<std::string>{"taken"});  // the temporary is gone
}

TEST_F(AtomicWrite, WritePackingThenReadPackingRoundTrips) {
  Scene scene;
  scene.cell.size = Vec2(4.0, 4.0);
  scene.particles.resize(2);
  scene.particles[0].position = Vec2(1.0, 1.0);
  scene.particles[1].position = Vec2(3.0, 1.0 + 1e-15);
  scene.provenance = "test\nwith newline";
  const fs::path path = dir_ / "scene.unjam";
  WritePacking(scene, path);
  const Scene read = ReadPacking(path);
  EXPECT_EQ(read.particles[1].position.y(), 1.0 + 1e-15);
  EXPECT_EQ(read.provenance, scene.provenance);
  EXPECT_EQ(Entries(), std::vector<std::string>{"scene.unjam"});
}

TEST_F(AtomicWrite, ReadingADirectoryIsAnInputError) {
  EXPECT_THROW(ReadPacking(dir_), InputError);
}

}  // namespace
}  // namespace unjam
