// Tests for src/io/packing_file.cpp: every class of bad input gives an InputError with the
// right line and a useful message.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "unjam/io/packing_file.hpp"

namespace unjam {
namespace {

// A valid file (line numbers on the right) that each case edits.
const std::vector<std::string> kValid = {
    "unjam-packing 1",          // 1
    "cell 4 4",                 // 2
    "periodic xy",              // 3
    "friction 0.5",             // 4
    "particles 3",              // 5
    "0.5 0.5 0 0 0 0 0.5 1 0",  // 6
    "1.5 0.5 0 0 0 0 0.5 1 0",  // 7
    "0.5 1.5 0 0 0 0 0.5 1 0",  // 8
    "end",                      // 9
};

std::string Join(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

// kValid with line `number` (1-based) replaced by `replacement` (several lines allowed).
std::string Replace(int number, const std::string& replacement) {
  std::vector<std::string> lines = kValid;
  lines[number - 1] = replacement;
  return Join(lines);
}

std::string InsertBefore(int number, const std::string& inserted) {
  std::vector<std::string> lines = kValid;
  lines.insert(lines.begin() + (number - 1), inserted);
  return Join(lines);
}

std::string Repeat(const std::string& piece, int times) {
  std::string out;
  for (int k = 0; k < times; ++k) out += piece;
  return out;
}

struct ErrorCase {
  std::string name;
  std::string text;
  int line;
  std::string message;  // a substring of what()
};

void PrintTo(const ErrorCase& c, std::ostream* os) { *os << c.name; }

class PackingErrors : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(PackingErrors, RaisesInputErrorWithLineAndMessage) {
  const ErrorCase& c = GetParam();
  try {
    ParsePacking(c.text, "case.unjam");
    FAIL() << "accepted:\n" << c.text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "case.unjam");
    EXPECT_EQ(e.line(), c.line) << e.what();
    EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("case.unjam:" + std::to_string(c.line) + ": ", 0), 0u)
        << e.what();
  }
}

std::vector<ErrorCase> Cases() {
  const std::string particle = "0.5 0.5 0 0 0 0 0.5 1 0";
  return {
      {"EmptyFile", "", 1, "missing header"},
      {"OnlyComments", "# nothing\n\n", 2, "missing header"},
      {"WrongHeader", Replace(1, "unjam-packing-x 1"), 1, "missing header"},
      {"NoHeader", Join({kValid.begin() + 1, kValid.end()}), 1, "missing header"},
      {"FutureVersion", Replace(1, "unjam-packing 2"), 1, "unsupported format version 2"},
      {"MalformedVersion", Replace(1, "unjam-packing 1.0"), 1, "format version"},
      {"HeaderWithoutVersion", Replace(1, "unjam-packing"), 1, "expects 1 value"},
      {"TrailingGarbage", Replace(6, "0.5 0.5 0 0 0 0 1.0abc 1 0"), 6, "malformed number '1.0abc'"},
      {"DoubleSign", Replace(6, "0.5 +-0.5 0 0 0 0 0.5 1 0"), 6, "malformed number"},
      {"HexFloat", Replace(6, "0x1p-1 0.5 0 0 0 0 0.5 1 0"), 6, "malformed number"},
      {"TooFewFields", Replace(6, "0.5 0.5 0 0 0 0 0.5 1"), 6, "9 fields"},
      {"TooManyFields", Replace(6, particle + " 0"), 6, "9 fields"},
      {"HugeFieldCount", Replace(6, particle + Repeat(" 1", 100000)), 6, "9 fields"},
      {"CellWithOneValue", Replace(2, "cell 4"), 2, "expects 2 value"},
      {"NaN", Replace(7, "nan 0.5 0 0 0 0 0.5 1 0"), 7, "NaN or infinity"},
      {"NegativeNaN", Replace(7, "1.5 -nan 0 0 0 0 0.5 1 0"), 7, "NaN or infinity"},
      {"Inf", Replace(4, "friction inf"), 4, "NaN or infinity"},
      {"NegativeInfinity", Replace(2, "cell 4 -infinity"), 2, "NaN or infinity"},
      {"Overflow", Replace(7, "1.5 0.5 1e400 0 0 0 0.5 1 0"), 7, "outside the range"},
      {"Underflow", Replace(7, "1.5 0.5 1e-400 0 0 0 0.5 1 0"), 7, "outside the range"},
      {"ZeroRadius", Replace(8, "0.5 1.5 0 0 0 0 0 1 0"), 8, "radius must be positive"},
      {"NegativeRadius", Replace(8, "0.5 1.5 0 0 0 0 -0.5 1 0"), 8, "radius must be positive"},
      {"ZeroDensity", Replace(8, "0.5 1.5 0 0 0 0 0.5 0 0"), 8, "density must be positive"},
      {"NegativeDensity", Replace(8, "0.5 1.5 0 0 0 0 0.5 -2 0"), 8, "density must be positive"},
      {"BadFixedFlag", Replace(8, "0.5 1.5 0 0 0 0 0.5 1 2"), 8, "fixed must be 0 or 1"},
      {"ZeroCell", Replace(2, "cell 0 4"), 2, "cell size must be positive"},
      {"NegativeCell", Replace(2, "cell 4 -4"), 2, "cell size must be positive"},
      {"FewerParticlesThanDeclared", Replace(5, "particles 4"), 9,
       "expected 4 particle line(s), found 3"},
      {"MoreParticlesThanDeclared", Replace(5, "particles 2"), 8,
       "more particle lines than the declared 2"},
      {"NegativeCount", Replace(5, "particles -1"), 5, "particle count"},
      {"NonIntegerCount", Replace(5, "particles 2.5"), 5, "particle count"},
      {"AbsurdCount", Replace(5, "particles 99999999999999999999"), 5, "particle count"},
      {"LargeCountSmallFile", Replace(5, "particles 2000000000"), 9,
       "expected 2000000000 particle"},
      {"UnknownKey", InsertBefore(2, "colour red"), 2, "unknown key 'colour'"},
      {"BinaryKey", InsertBefore(2, std::string("\x01\xff\0x", 4)), 2,
       "unknown key '\\x01\\xff\\x00x'"},
      {"DuplicateCell", InsertBefore(3, "cell 5 5"), 3,
       "duplicate key 'cell' (first given on line 2)"},
      {"DuplicateFriction", InsertBefore(5, "friction 0.1"), 5, "duplicate key 'friction'"},
      {"NegativeFriction", Replace(4, "friction -0.1"), 4, "friction must not be negative"},
      {"UnknownPeriodicity", Replace(3, "periodic y"), 3, "periodic must be none, x or xy"},
      {"NonUnitWallNormal", InsertBefore(3, "wall 0 0 0 1.000001"), 3, "unit vector"},
      {"RescaledWallNormal", InsertBefore(3, "wall 0 0 0 2"), 3, "unit vector"},
      {"ForceIndexOutOfRange", InsertBefore(9, "forces 1\n0 3 0 0 1 0"), 10,
       "force particle j = 3 out of range"},
      {"ForceWallOutOfRange", InsertBefore(9, "forces 1\n0 -1 0 0 1 0"), 10,
       "wall 0) out of range (0 walls)"},
      {"ForceSelfPair", InsertBefore(9, "forces 1\n1 1 0 0 1 0"), 10, "two different particles"},
      {"ForceImageTooLarge", InsertBefore(9, "forces 1\n0 1 2 0 1 0"), 10, "image x"},
      {"ForceDuplicated", InsertBefore(9, "forces 2\n0 1 0 0 1 0\n0 1 0 0 2 0"), 11,
       "duplicate force of particles 0 and 1 (image 0 0; first given on line 10)"},
      {"ForceDuplicatedReversed",
       InsertBefore(9, "forces 3\n0 2 0 0 1 0\n0 1 1 0 1 0\n1 0 -1 0 1 0"), 12,
       "duplicate force of particles 1 and 0 (image -1 0; first given on line 11)"},
      {"ForceDuplicatedOnWall",
       Replace(3, "periodic x\nwall 0 0 0 1\nforces 2\n0 -1 0 0 1 0\n0 -1 0 0 1 0"), 7,
       "duplicate force of particle 0 on wall 0 (first given on line 6)"},
      {"ForceNegativeNormal", InsertBefore(9, "forces 1\n0 1 0 0 -1e-300 0"), 10,
       "normal force must not be negative"},
      {"ForceMissingLine", InsertBefore(9, "forces 2\n0 1 0 0 1 0"), 11,
       "expected 2 force line(s), found 1"},
      {"MotionOutOfRange", InsertBefore(5, "prescribed-motion 3 0 0 0"), 5,
       "out of range (3 particles)"},
      {"MotionTwice", InsertBefore(5, "prescribed-motion 1 0 0 0\nprescribed-motion 1 1 0 0"), 6,
       "already has"},
      {"GapOutOfRange", InsertBefore(5, "prescribed-gap 0 5 0 0 0"), 5, "out of range"},
      {"GapSamePair", InsertBefore(5, "prescribed-gap 2 2 0 0 0"), 5, "two different particles"},
      {"ImageAlongNonPeriodicAxis", Replace(3, "periodic x\nprescribed-gap 0 1 0 1 0"), 4,
       "image y must be 0"},
      {"OutsidePeriodicCell", Replace(7, "4 0.5 0 0 0 0 0.5 1 0"), 7,
       "x = 4 lies outside the periodic cell [0, 4)"},
      {"NegativeInPeriodicCell", Replace(8, "0.5 -0.25 0 0 0 0 0.5 1 0"), 8,
       "y = -0.25 lies outside"},
      {"Overlap", Replace(7, "1.25 0.5 0 0 0 0 0.5 1 0"), 7, "particles 0 and 1 overlap by 0.25"},
      {"OverlapAcrossBoundary", Replace(7, "3.75 0.5 0 0 0 0 0.5 1 0"), 7,
       "particles 0 and 1 overlap by 0.25"},
      {"WallOverlap", Replace(3, "periodic none\nwall 0 0.25 0 1"), 7,
       "particle 0 overlaps wall 0 by 0.25"},
      {"CellTooSmall", Replace(8, "0.5 1.5 0 0 0 0 1.5 1 0"), 2, "too small"},
      {"MissingEnd", Join({kValid.begin(), kValid.end() - 1}), 8, "truncated: missing 'end'"},
      {"TruncatedParticles", Join({kValid.begin(), kValid.begin() + 6}), 6,
       "truncated: expected 3 particle"},
      {"ContentAfterEnd", Join(kValid) + "cell 1 1\n", 10, "after 'end'"},
      {"EndWithValue", Replace(9, "end now"), 9, "expects 0 value"},
      {"MissingCell", Replace(2, "# no cell"), 9, "missing 'cell'"},
      {"MissingParticles", Join({kValid[0], kValid[1], "end"}), 3, "missing 'particles'"},
      {"LongGarbageLine", InsertBefore(2, Repeat("\xfe", 1 << 20)), 2, "unknown key '\\xfe\\xfe"},
      {"EmbeddedNul", Replace(2, std::string("cell 4\0 4", 9)), 2, "malformed number '4\\x00'"},
      {"NegativeSeed", InsertBefore(5, "seed -1"), 5, "seed"},
      {"BadEscape", InsertBefore(5, "provenance a\\qb"), 5, "bad escape"},
      {"PressureBathNeedsXY", Replace(3, "periodic x\npressure-bath 1 100 0"), 4, "fully periodic"},
      {"PressureBathMass", InsertBefore(5, "pressure-bath 1 0 0"), 5, "cell mass must be positive"},
  };
}

INSTANTIATE_TEST_SUITE_P(AllClasses, PackingErrors, ::testing::ValuesIn(Cases()),
                         [](const ::testing::TestParamInfo<ErrorCase>& info) {
                           return info.param.name;
                         });

TEST(PackingErrorsBase, TheBaseFileIsValid) {
  EXPECT_NO_THROW(ParsePacking(Join(kValid), "base.unjam"));
}

// Two contacts of one pair through different periodic images are two contacts; a normal
// force of −0 is zero.
TEST(PackingErrorsBase, ForcesOfOnePairAtOtherImagesAndNegativeZeroAreAccepted) {
  const Scene scene = ParsePacking(
      InsertBefore(9, "forces 3\n0 1 0 0 1 0\n0 1 -1 0 1 0\n1 0 -1 0 -0 0"), "images.unjam");
  EXPECT_EQ(scene.forces.size(), 3u);
}

}  // namespace
}  // namespace unjam
