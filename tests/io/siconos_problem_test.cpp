// Tests for src/io/siconos_reader.cpp and src/io/siconos_writer.cpp: the hand-written
// problems of problems/siconos in every storage, bit-exact round trips, and errors that
// name the file and the line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "unjam/io/packing_file.hpp"
#include "unjam/io/siconos_problem.hpp"

namespace unjam {
namespace {

namespace fs = std::filesystem;

std::string Problem(const std::string& name) {
  return std::string(UNJAM_SOURCE_DIR) + "/problems/siconos/" + name;
}

Eigen::MatrixXd DenseW(const DelassusProblem& p) { return Eigen::MatrixXd(p.w); }

TEST(SiconosRead, OneContactInDenseStorage) {
  const DelassusProblem p = ReadSiconosProblem(Problem("one-contact-stick.dat"));
  ASSERT_EQ(p.NumContacts(), 1);
  EXPECT_EQ(DenseW(p), (Eigen::Matrix2d() << 2, 0, 0, 4).finished());
  EXPECT_EQ(p.q, Eigen::Vector2d(-1.0, 0.4));
  EXPECT_EQ(p.laws[0].mu, 1.0);
  EXPECT_EQ(p.laws[0].kind, ConstraintKind::kUnilateral);
  EXPECT_EQ(p.w.nonZeros(), 2);  // explicit zeros are not stored
}

TEST(SiconosRead, CoupledBlockInCscStorage) {
  const DelassusProblem p = ReadSiconosProblem(Problem("coupled-block-slide.dat"));
  EXPECT_EQ(DenseW(p), (Eigen::Matrix2d() << 2, 1, 1, 4).finished());
  EXPECT_EQ(p.q, Eigen::Vector2d(-1.0, 4.0));
  EXPECT_EQ(p.laws[0].mu, 0.2);
}

TEST(SiconosRead, EveryStorageParsesToTheSameProblem) {
  const DelassusProblem dense = ReadSiconosProblem(Problem("two-contacts-stick-dense.dat"));
  Eigen::Matrix4d expected;
  expected << 2, 0, -1, 0, 0, 3, 0, 0.5, -1, 0, 2, 0, 0, 0.5, 0, 3;
  EXPECT_EQ(DenseW(dense), expected);
  for (const char* name : {"two-contacts-stick-block.dat", "two-contacts-stick-triplet.dat",
                           "two-contacts-stick-csc.dat"}) {
    const DelassusProblem p = ReadSiconosProblem(Problem(name));
    EXPECT_EQ(DenseW(p), expected) << name;
    EXPECT_EQ(p.q, dense.q) << name;
    ASSERT_EQ(p.NumContacts(), 2) << name;
    for (int k = 0; k < 2; ++k) EXPECT_EQ(p.laws[k].mu, 0.5) << name;
  }
}

TEST(SiconosRead, RepeatedSparseEntriesAreSummedAsCSparseDoes) {
  const std::string text =
      "2\n1\n2\n2\n2\n1\nheader\ntriplet: 2-by-2, nzmax: 3 nnz: 3\n"
      "    0 0 : 1.5\n    1 1 : 4\n    0 0 : 0.5\n-1 0\n0.1\n";
  EXPECT_EQ(DenseW(ParseSiconosProblem(text, "sum.dat")),
            (Eigen::Matrix2d() << 2, 0, 0, 4).finished());
}

// A random problem with awkward doubles: round trips must give back the same bits.
DelassusProblem RandomProblem(int nc, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, 2 * nc - 1);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < 2 * nc; ++i) t.emplace_back(i, i, 1.0 + std::abs(u(rng)));
  // Off the diagonal only: the reader refuses a W whose diagonal is not positive.
  for (int e = 0; e < 3 * nc; ++e) {
    const int row = pick(rng), col = pick(rng);
    const double value = u(rng) * std::pow(10.0, 40.0 * u(rng));
    if (row != col) t.emplace_back(row, col, value);
  }
  t.emplace_back(0, 2 * nc - 1, 0.1);
  t.emplace_back(2 * nc - 1, 0, 4.9406564584124654e-324);  // the smallest subnormal
  DelassusProblem p;
  p.w.resize(2 * nc, 2 * nc);
  p.w.setFromTriplets(t.begin(), t.end());
  p.q = Eigen::VectorXd::NullaryExpr(2 * nc, [&] { return u(rng) / 3.0; });
  for (int k = 0; k < nc; ++k)
    p.laws.push_back({k == 0 ? 0.0 : std::abs(u(rng)), ConstraintKind::kUnilateral});
  return p;
}

void ExpectSameBits(const DelassusProblem& a, const DelassusProblem& b) {
  ASSERT_EQ(a.NumContacts(), b.NumContacts());
  const Eigen::MatrixXd wa = DenseW(a), wb = DenseW(b);
  for (Eigen::Index i = 0; i < wa.size(); ++i)
    ASSERT_EQ(wa.data()[i], wb.data()[i]) << "W entry " << i;
  for (Eigen::Index i = 0; i < a.q.size(); ++i) ASSERT_EQ(a.q[i], b.q[i]) << "q " << i;
  for (int k = 0; k < a.NumContacts(); ++k) ASSERT_EQ(a.laws[k].mu, b.laws[k].mu) << "mu " << k;
}

TEST(SiconosWrite, RoundTripIsBitExactInBothStorages) {
  for (SiconosStorage storage : {SiconosStorage::kSparseBlock, SiconosStorage::kDense}) {
    const DelassusProblem p = RandomProblem(7, 11);
    const std::string text = FormatSiconosProblem(p, storage);
    const DelassusProblem back = ParseSiconosProblem(text, "roundtrip.dat");
    ExpectSameBits(p, back);
    EXPECT_EQ(FormatSiconosProblem(back, storage), text);  // write → read → write is the identity
  }
}

TEST(SiconosWrite, SparseBlockLayoutHasEveryDiagonalBlockAndOnlyStoredOthers) {
  // Contact 1 couples to nothing: its diagonal block is written anyway (Siconos' NSGS reads
  // it); of the off-diagonal blocks only (0, 2) holds an entry.
  DelassusProblem p;
  p.w.resize(6, 6);
  p.w.insert(0, 0) = 2.0;
  p.w.insert(1, 5) = -0.5;
  p.w.insert(4, 4) = 3.0;
  p.q = Eigen::VectorXd::Constant(6, -1.0);
  p.laws.assign(3, ContactLaw{0.25, ConstraintKind::kUnilateral});
  const std::string text = FormatSiconosProblem(p);
  EXPECT_EQ(text,
            "2\n3\n1\n6\n6\n"
            "4\n3\n3\n2 4 6\n2 4 6\n4\n4\n0 2 3 4\n0 2 1 2\n"
            "0\n2 0 0 0\n1\n0 0 0 -0.5\n2\n0 0 0 0\n3\n3 0 0 0\n"
            "-1 -1 -1 -1 -1 -1\n0.25 0.25 0.25\n");
  // Such a W (zero diagonal entries) is no Delassus operator: the reader refuses it.
  try {
    ParseSiconosProblem(text, "layout.dat");
    ADD_FAILURE() << "a W with zero diagonal entries was read";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("contact 0: W[1][1] (its tangential diagonal entry) is 0"),
              std::string::npos)
        << e.what();
  }
}

TEST(SiconosWrite, HeldContactIsRefusedAndNoFileIsLeft) {
  DelassusProblem p = RandomProblem(2, 3);
  p.laws[1].kind = ConstraintKind::kBilateral;
  EXPECT_THROW(FormatSiconosProblem(p), std::invalid_argument);
  const fs::path dir = fs::temp_directory_path() / ("unjam_siconos_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  try {
    WriteSiconosProblem(p, dir / "held.dat");
    ADD_FAILURE() << "no error";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("held.dat"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("contact 1"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir));
  EXPECT_THROW(WriteSiconosProblem(RandomProblem(2, 3), dir / "no" / "such" / "p.dat"),
               OutputError);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

TEST(SiconosWrite, ImpulsesOneContactPerLine) {
  const fs::path path =
      fs::temp_directory_path() / ("unjam_impulses_" + std::to_string(::getpid()) + ".txt");
  WriteImpulses(Eigen::Vector4d(0.5, -0.1, 0.0, 1e-300), path);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "0.5 -0.1\n0 1e-300\n");
  fs::remove(path);
  EXPECT_THROW(WriteImpulses(Eigen::Vector3d(1, 2, 3), path), OutputError);
  EXPECT_FALSE(fs::exists(path));
}

// Malformed text → the error names the file and this line, and says what is wrong.
struct BadCase {
  const char* what;
  std::string text;
  int line;
  const char* message;
};

const std::string kGood = "2\n1\n0\n2\n2\n2 2\n2 0\n0 4\n-1 0.4\n1\n";
const std::string kBlockHead = "2\n2\n1\n4\n4\n";
const std::string kTail = "-1 0 -1 0\n0.5 0.5\n";

std::vector<BadCase> BadCases() {
  return {
      {"3D problem", "3\n1\n", 1, "dimension 3"},
      {"no contacts", "2\n0\n", 2, "number of contacts"},
      {"too many contacts for the file", "2\n100000000\n0\n", 2, "truncated"},
      {"unknown storage", "2\n1\n5\n2\n2\n", 3, "storage type"},
      {"W of the wrong size", "2\n1\n0\n3\n3\n", 3, "W is 3 x 3, expected 2 x 2"},
      {"non-square dense sizes", "2\n1\n0\n2\n2\n2 3\n", 6, "dense matrix is 2 x 3"},
      {"missing numbers", "2\n1\n0\n2\n2\n2 2\n2 0\n0 4\n-1 0.4\n", 9, "truncated: expected mu[0]"},
      {"extra numbers", kGood + "7\n", 11, "unexpected data after the friction coefficients: '7'"},
      {"NaN in W", "2\n1\n0\n2\n2\n2 2\n2 0\nnan 4\n-1 0.4\n1\n", 8, "NaN"},
      {"infinite q", "2\n1\n0\n2\n2\n2 2\n2 0\n0 4\n-inf 0.4\n1\n", 9, "q[0]"},
      {"negative friction", "2\n1\n0\n2\n2\n2 2\n2 0\n0 4\n-1 0.4\n-0.5\n", 10, "must be >= 0"},
      {"malformed number", "2\n1\n0\n2\n2\n2 2\n2 0abc\n0 4\n-1 0.4\n1\n", 7,
       "malformed number '0abc'"},
      {"block of size 3", kBlockHead + "2\n2\n2\n3 4\n", 9,
       "bad block structure: block row end 0 is 3"},
      {"block rows not per contact", kBlockHead + "2\n1\n1\n" + kTail, 7,
       "number of block rows is 1"},
      {"block pointers falling", kBlockHead + "2\n2\n2\n2 4\n2 4\n3\n2\n0 2 1\n", 13,
       "block row pointer 2"},
      {"block columns not increasing", kBlockHead + "2\n2\n2\n2 4\n2 4\n3\n2\n0 2 2\n1 0\n", 14,
       "must increase"},
      {"block column out of range", kBlockHead + "2\n2\n2\n2 4\n2 4\n3\n2\n0 1 2\n0 2\n", 14,
       "block column index"},
      {"block numbered wrongly", kBlockHead + "2\n2\n2\n2 4\n2 4\n3\n2\n0 1 2\n0 1\n1\n", 15,
       "block number 1, expected 0"},
      {"CSR origin", "2\n1\n2\n2\n2\n3\nh\n", 6, "CSR is not"},
      {"text after the origin", "2\n1\n2\n2\n2\n2 x\nh\n", 6, "after the sparse origin"},
      {"CSC size mismatch", "2\n1\n2\n2\n2\n2\nh\n4-by-4, nzmax: 1 nnz: 1, 1-norm: 1\n", 8,
       "W is 4 x 4"},
      {"triplet size line for CSC", "2\n1\n2\n2\n2\n2\nh\ntriplet: 2-by-2, nzmax: 1 nnz: 1\n", 8,
       "origin 2, CSC"},
      {"CSC column skipped",
       "2\n1\n2\n2\n2\n2\nh\n2-by-2, nzmax: 1 nnz: 1, 1-norm: 1\n    col 1 : locations 0 to 0\n", 9,
       "expected column 0"},
      {"CSC row out of range",
       "2\n1\n2\n2\n2\n2\nh\n2-by-2, nzmax: 1 nnz: 1, 1-norm: 1\n    col 0 : locations 0 to 0\n    "
       "  2 : 1\n",
       10, "row index"},
      {"CSC fewer entries than said",
       "2\n1\n2\n2\n2\n2\nh\n2-by-2, nzmax: 2 nnz: 2, 1-norm: 1\n    col 0 : locations 0 to 0\n    "
       "  0 : 1\n    col 1 : locations 1 to 0\n1 1\n1\n",
       11, "1 entries listed, the size line says 2"},
      {"triplet entry without a value",
       "2\n1\n2\n2\n2\n1\nh\ntriplet: 2-by-2, nzmax: 1 nnz: 1\n    0 0 :\n", 9, "I J : VALUE"},
      {"triplet NaN value",
       "2\n1\n2\n2\n2\n1\nh\ntriplet: 2-by-2, nzmax: 1 nnz: 1\n    0 0 : nan\n", 9, "NaN"},
      {"truncated sparse section", "2\n1\n2\n2\n2\n1\nh\ntriplet: 2-by-2, nzmax: 1 nnz: 1\n", 8,
       "truncated"},
      // Not a Delassus operator (H M^-1 H^T has a positive diagonal): named at W's first line.
      {"negative diagonal of W", "2\n1\n0\n2\n2\n2 2\n-2 0\n0 -4\n-1 0.4\n1\n", 3,
       "contact 0: W[0][0] (its normal diagonal entry) is -2, not positive: W is not a Delassus "
       "operator"},
      {"W of no blocks (zero)", "2\n1\n1\n2\n2\n0\n-1 0.4\n1\n", 3,
       "contact 0: W[0][0] (its normal diagonal entry) is 0"},
      {"zero tangential diagonal of contact 1",
       kBlockHead + "2\n2\n2\n2 4\n2 4\n3\n2\n0 1 2\n0 1\n0\n2 0 0 3\n1\n2 0 0 0\n" + kTail, 3,
       "contact 1: W[3][3] (its tangential diagonal entry) is 0"},
      {"diagonal summed to zero (triplet)",
       "2\n1\n2\n2\n2\n1\nh\ntriplet: 2-by-2, nzmax: 3 nnz: 3\n    0 0 : 1\n    1 1 : 1\n    0 0 : "
       "-1\n-1 0\n1\n",
       3, "contact 0: W[0][0]"},
  };
}

TEST(SiconosRead, MalformedInputNamesFileLineAndProblem) {
  for (const BadCase& c : BadCases()) {
    try {
      ParseSiconosProblem(c.text, "bad.dat");
      ADD_FAILURE() << c.what << ": no error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "bad.dat") << c.what;
      EXPECT_EQ(e.line(), c.line) << c.what << ": " << e.what();
      EXPECT_NE(e.message().find(c.message), std::string::npos) << c.what << ": " << e.what();
      const std::string prefix = "bad.dat:" + std::to_string(c.line) + ": ";
      EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
    }
  }
  EXPECT_NO_THROW(ParseSiconosProblem(kGood, "good.dat"));
  EXPECT_NO_THROW(ParseSiconosProblem(
      kBlockHead + "2\n2\n2\n2 4\n2 4\n3\n2\n0 1 2\n0 1\n0\n2 0 0 3\n1\n2 0 0 3\n" + kTail,
      "good.dat"));
}

TEST(SiconosRead, MissingFileIsAnInputError) {
  EXPECT_THROW(ReadSiconosProblem("/nonexistent/problem.dat"), InputError);
}

}  // namespace
}  // namespace unjam
