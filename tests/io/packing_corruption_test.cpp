// Tests for src/io/packing_file.cpp: seeded corruptions of valid files either parse or
// raise InputError, never anything else (no other exception, crash or hang).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "io/mutations.hpp"
#include "io/random_scene.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {
namespace {

TEST(PackingCorruption, MutatedFilesParseOrRaiseInputErrorOnly) {
  std::mt19937_64 rng(987654321);
  std::vector<std::string> originals;
  for (int k = 0; k < 20; ++k) originals.push_back(FormatPacking(testing::RandomScene(rng)));
  int accepted = 0;
  int rejected = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const std::string text = testing::Mutate(originals[trial % originals.size()], rng);
    try {
      ParsePacking(text, "mutant.unjam");
      ++accepted;
    } catch (const InputError& e) {
      ++rejected;
      ASSERT_EQ(std::string(e.what()).rfind("mutant.unjam", 0), 0u) << e.what();
    } catch (const std::exception& e) {
      FAIL() << "trial " << trial << ": unexpected exception " << e.what() << "\n" << text;
    } catch (...) {
      FAIL() << "trial " << trial << ": unexpected non-standard exception\n" << text;
    }
  }
  RecordProperty("accepted", accepted);
  RecordProperty("rejected", rejected);
  std::printf("corruption: %d accepted, %d rejected\n", accepted, rejected);
  // Both outcomes must occur, or the mutations are not exercising the reader.
  EXPECT_GT(accepted, 100);
  EXPECT_GT(rejected, 5000);
}

}  // namespace
}  // namespace unjam
