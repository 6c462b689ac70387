#include "unjam/io/read_text.hpp"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "unjam/io/packing_file.hpp"

namespace unjam {
namespace {

std::filesystem::path TextFile(const std::string& name, const std::string& text) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(ReadInputText, ReadsAFileUpToTheBoundAndRefusesOneAboveIt) {
  const std::filesystem::path path = TextFile("unjam-read-text-test.txt", std::string(100, 'x'));
  EXPECT_EQ(ReadInputText(path, 100), std::string(100, 'x'));
  try {
    ReadInputText(path, 99);
    FAIL() << "a file above the bound was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unjam-read-text-test.txt"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

// A device that never ends is refused at the bound instead of filling memory.
TEST(ReadInputText, RefusesAnEndlessDevice) {
  if (!std::filesystem::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  EXPECT_THROW(ReadInputText("/dev/zero", std::size_t{1} << 20), InputError);
}

TEST(ReadInputText, NamesAMissingFile) {
  EXPECT_THROW(ReadInputText("/nonexistent/unjam-input"), InputError);
}

}  // namespace
}  // namespace unjam
