// Tests for src/io/output_lock.cpp: one holder at a time, a clear refusal, and a lock that
// goes with its process however it ends.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <optional>
#include <string>

#include "temp_dir_test.hpp"
#include "unjam/io/output_lock.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {
namespace {

namespace fs = std::filesystem;

class OutputLockTest : public testing::TempDirTest {
 protected:
  OutputLockTest() : TempDirTest("unjam_lock_") {}

  // The message of the OutputError that taking `path` throws, or "" if it is taken.
  static std::string Refusal(const fs::path& path) {
    try {
      OutputLock lock(path, "out");
    } catch (const OutputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(OutputLockTest, ASecondHolderIsRefusedNamingTheOutputTheLockAndTheFirst) {
  const fs::path path = dir_ / ".lock";
  std::optional<OutputLock> first(std::in_place, path, "out");
  const std::string refusal = Refusal(path);
  EXPECT_NE(refusal.find("out is being written by another run"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find(path.string()), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("process " + std::to_string(::getpid()) + " on "), std::string::npos)
      << refusal;
  first.reset();
  EXPECT_FALSE(fs::exists(path)) << "released, the lock file is removed";
  EXPECT_EQ(Refusal(path), "");
}

TEST_F(OutputLockTest, AKilledHolderLeavesAFileThatHoldsNothing) {
  const fs::path path = dir_ / ".lock";
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {  // holds the lock until killed
    OutputLock lock(path, "out");
    (void)!::write(ready[1], "x", 1);
    for (;;) ::pause();
  }
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  EXPECT_NE(Refusal(path).find("process " + std::to_string(child) + " on "), std::string::npos);
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  ::close(ready[0]);
  ::close(ready[1]);
  EXPECT_TRUE(fs::exists(path)) << "a killed holder cannot remove its file";
  EXPECT_EQ(Refusal(path), "");
}

TEST_F(OutputLockTest, ALockFileThatCannotBeCreatedIsAnOutputError) {
  const std::string refusal = Refusal(dir_ / "no" / "such" / ".lock");
  EXPECT_NE(refusal.find("cannot create the lock file"), std::string::npos) << refusal;
}

}  // namespace
}  // namespace unjam
