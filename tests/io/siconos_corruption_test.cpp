// Tests for src/io/siconos_reader.cpp: seeded corruptions of valid Siconos problems either
// parse or raise InputError, never anything else (no other exception, crash or hang), and
// whatever parses is written and read back unchanged.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/mutations.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/siconos_problem.hpp"

namespace unjam {
namespace {

std::vector<std::string> Originals() {
  std::vector<std::string> texts;
  for (const char* name :
       {"one-contact-stick.dat", "one-contact-slide.dat", "one-contact-open.dat",
        "coupled-block-slide.dat", "two-contacts-stick-dense.dat", "two-contacts-stick-block.dat",
        "two-contacts-stick-triplet.dat", "two-contacts-stick-csc.dat", "two-contacts-open.dat"}) {
    std::ifstream in(std::string(UNJAM_SOURCE_DIR) + "/problems/siconos/" + name);
    std::ostringstream text;
    text << in.rdbuf();
    texts.push_back(text.str());
  }
  return texts;
}

TEST(SiconosCorruption, MutatedFilesParseOrRaiseInputErrorOnly) {
  std::mt19937_64 rng(123456789);
  const std::vector<std::string> originals = Originals();
  int accepted = 0;
  int rejected = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const std::string text = testing::Mutate(originals[trial % originals.size()], rng);
    try {
      const DelassusProblem p = ParseSiconosProblem(text, "mutant.dat");
      ++accepted;
      const std::string written = FormatSiconosProblem(p);
      ASSERT_EQ(FormatSiconosProblem(ParseSiconosProblem(written, "rewritten.dat")), written)
          << text;
    } catch (const InputError& e) {
      ++rejected;
      ASSERT_EQ(std::string(e.what()).rfind("mutant.dat", 0), 0u) << e.what();
    } catch (const std::exception& e) {
      FAIL() << "trial " << trial << ": unexpected exception " << e.what() << "\n" << text;
    } catch (...) {
      FAIL() << "trial " << trial << ": unexpected non-standard exception\n" << text;
    }
  }
  std::printf("siconos corruption: %d accepted, %d rejected\n", accepted, rejected);
  // Both outcomes must occur, or the mutations are not exercising the reader.
  EXPECT_GT(accepted, 100);
  EXPECT_GT(rejected, 5000);
}

}  // namespace
}  // namespace unjam
