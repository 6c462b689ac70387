// The 2D local-form problems of Siconos' own test collection (problems/siconos/collection,
// README.md there): every file is read, and nsgs and newton give either a converged answer
// within the tolerance or say that they did not converge, never NaN or Inf. Also the
// trailing `isComplete` flag of files written before 2010, which src/io/siconos_reader.cpp
// reads, and the refusal of Siconos' global form (M, H, q, b).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "unjam/io/packing_file.hpp"
#include "unjam/io/siconos_problem.hpp"
#include "unjam/solvers/contact_solver.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {
namespace {

namespace fs = std::filesystem;

const fs::path kCollection = fs::path(UNJAM_SOURCE_DIR) / "problems" / "siconos" / "collection";

std::vector<fs::path> CollectionFiles() {
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(kCollection)) {
    if (e.path().extension() == ".dat") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Contacts per bundled file, from its header: a file that goes missing or reads differently
// is noticed.
int ExpectedContacts(const std::string& name) {
  if (name.rfind("FC2D_SliderCrankLagrangian", 0) == 0) return 2;
  if (name == "FrictionContactProblem00031.dat") return 11;
  if (name == "FrictionContactProblem00071.dat") return 89;
  if (name == "FrictionContactProblem00237.dat") return 376;
  if (name == "FrictionContactProblem00374.dat") return 28;
  if (name == "FrictionContactProblem00394.dat") return 6;
  if (name == "FrictionContactProblem00727.dat") return 367;
  if (name == "fc2d_granularflowonwall_00667_00000.dat") return 667;
  return -1;
}

bool AllFinite(const Eigen::VectorXd& v) { return v.allFinite(); }

TEST(SiconosCollection, EveryFileIsReadAndSolvedHonestly) {
  // Measured on one core (Release): every file/backend pair below takes under 0.1 s, so
  // none is skipped. The larger fc2d_granularflowonwall_02020_00213 (797 KB, not bundled)
  // takes 6.5 s (nsgs) and 27 s (newton) without converging to 1e-10.
  const std::vector<fs::path> files = CollectionFiles();
  ASSERT_EQ(files.size(), 9u) << kCollection;
  for (const fs::path& file : files) {
    const std::string name = file.filename().string();
    SCOPED_TRACE(name);
    const DelassusProblem p = ReadSiconosProblem(file);
    EXPECT_EQ(p.NumContacts(), ExpectedContacts(name));
    ASSERT_TRUE(AllFinite(p.q));
    for (const char* backend : {"nsgs", "newton"}) {
      SCOPED_TRACE(backend);
      SolverOptions o;
      const SolveResult r = MakeSolver(backend)->SolveDelassus(p, o);
      ASSERT_EQ(r.impulses.size(), 2 * p.NumContacts());
      EXPECT_TRUE(AllFinite(r.impulses));
      EXPECT_TRUE(std::isfinite(r.report.residual)) << r.report.residual;
      // The reported residual is that of the returned impulses, recomputed here.
      const double residual = ComputeResidual(p, r.impulses).residual;
      EXPECT_TRUE(std::isfinite(residual));
      EXPECT_TRUE(std::isfinite(SiconosError(p, r.impulses)));
      if (r.report.converged()) {
        EXPECT_LE(r.report.residual, o.tolerance) << r.report.message;
        EXPECT_LE(residual, o.tolerance) << r.report.message;
      } else {
        // A not-converged status: neither "unsupported" nor an answer to another model.
        EXPECT_TRUE(r.report.status == SolveStatus::kIterationLimit ||
                    r.report.status == SolveStatus::kNumericalFailure)
            << ToString(r.report.status) << ": " << r.report.message;
      }
    }
  }
}

// Lemke's exact pivoting solves every file of the collection to round-off. Left out:
// fc2d_granularflowonwall_00667_00000, which it also solves (residual 1.5e-15) but in 26 s.
TEST(SiconosCollection, LemkeSolvesEveryFileToRoundOff) {
  for (const fs::path& file : CollectionFiles()) {
    const std::string name = file.filename().string();
    if (name.rfind("fc2d_granularflowonwall", 0) == 0) continue;
    SCOPED_TRACE(name);
    const DelassusProblem p = ReadSiconosProblem(file);
    SolverOptions o;
    o.tolerance = 1e-10;
    const SolveResult r = MakeSolver("lemke")->SolveDelassus(p, o);
    EXPECT_TRUE(r.report.converged()) << r.report.message;
    EXPECT_LE(ComputeResidual(p, r.impulses).residual, 1e-12);
  }
}

// The De Saxcé fixed point of ipopt and nlopt needs a symmetric positive semidefinite W:
// where W is not symmetric (the slider crank) or has a negative eigenvalue (00237: one,
// about −8e-8; 00727: two, about −5e-8; NSGS, newton and lemke solve both) it refuses the
// problem up front, naming why; where it converges its residual is honest.
TEST(SiconosCollection, ConvexBackendsRefuseAnAsymmetricOrIndefiniteW) {
  struct Case {
    const char* file;
    const char* backend;
    SolveStatus status;
  };
  const std::vector<Case> cases = {
      {"FrictionContactProblem00237.dat", "ipopt", SolveStatus::kUnsupported},
      {"FrictionContactProblem00237.dat", "nlopt", SolveStatus::kUnsupported},
      {"FrictionContactProblem00727.dat", "ipopt", SolveStatus::kUnsupported},
      {"FrictionContactProblem00727.dat", "nlopt", SolveStatus::kUnsupported},
      {"FC2D_SliderCrankLagrangian00000.dat", "ipopt", SolveStatus::kUnsupported},
      {"FC2D_SliderCrankLagrangian00000.dat", "nlopt", SolveStatus::kUnsupported},
      {"FrictionContactProblem00374.dat", "ipopt", SolveStatus::kConverged},
      {"FrictionContactProblem00374.dat", "nlopt", SolveStatus::kConverged},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.file) + " " + c.backend);
    const DelassusProblem p = ReadSiconosProblem(kCollection / c.file);
    SolverOptions o;
    o.tolerance = 1e-10;
    const SolveResult r = MakeSolver(c.backend)->SolveDelassus(p, o);
    EXPECT_EQ(r.report.status, c.status) << r.report.message;
    ASSERT_TRUE(AllFinite(r.impulses));
    const double residual = ComputeResidual(p, r.impulses).residual;
    if (c.status == SolveStatus::kConverged) {
      EXPECT_LE(residual, o.tolerance);
    }
    if (c.status == SolveStatus::kUnsupported) {
      const bool indefinite = std::string(c.file).rfind("FrictionContactProblem", 0) == 0;
      EXPECT_NE(r.report.message.find(indefinite ? "not positive semidefinite" : "not symmetric"),
                std::string::npos)
          << r.report.message;
    }
  }
}

// A 1-contact dense problem, mu = 0.5 on line 10.
const std::string kProblem = "2\n1\n0\n2\n2\n2 2\n2 0\n0 4\n-1 0.4\n0.5\n";

TEST(SiconosCollection, TrailingCompletenessFlagIsRead) {
  for (const char* flag : {"1\n", "0\n", "1", "  1  \n\n", "1\r\n"}) {
    const DelassusProblem p = ParseSiconosProblem(kProblem + flag, "flag.dat");
    ASSERT_EQ(p.NumContacts(), 1) << flag;
    EXPECT_EQ(p.laws[0].mu, 0.5) << flag;
    EXPECT_EQ(p.q, Eigen::Vector2d(-1.0, 0.4)) << flag;
  }
  // The files that carry it in the collection read with it.
  const DelassusProblem p = ReadSiconosProblem(kCollection / "FrictionContactProblem00394.dat");
  EXPECT_EQ(p.NumContacts(), 6);
  for (const ContactLaw& law : p.laws) EXPECT_EQ(law.mu, 0.9);
}

TEST(SiconosCollection, OtherTrailingDataIsRefusedAtItsLine) {
  struct Case {
    std::string tail;
    int line;
    const char* token;
  };
  const std::vector<Case> cases = {
      {"2\n", 11, "'2'"},      // not a flag value
      {"1.0\n", 11, "'1.0'"},  // Siconos wrote it with %d
      {"1 1\n", 11, "'1'"},    // one flag only: the second is refused
      {"1\n0\n", 11, "'1'"},   // nor a second line
      {"\n\nx\n", 13, "'x'"}, {"-1\n", 11, "'-1'"},
  };
  for (const Case& c : cases) {
    try {
      ParseSiconosProblem(kProblem + c.tail, "tail.dat");
      ADD_FAILURE() << c.tail << ": read";
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), c.line) << c.tail << ": " << e.what();
      EXPECT_NE(e.message().find(std::string("unexpected data after the friction coefficients: ") +
                                 c.token),
                std::string::npos)
          << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("tail.dat:" + std::to_string(c.line) + ": ", 0), 0u)
          << e.what();
    }
  }
  // The flag on the line of the last mu is not how Siconos wrote it.
  try {
    ParseSiconosProblem("2\n1\n0\n2\n2\n2 2\n2 0\n0 4\n-1 0.4\n0.5 1\n", "same-line.dat");
    ADD_FAILURE() << "a flag on the mu line was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 10) << e.what();
  }
}

// Siconos' global form, as globalFrictionContact_printInFile writes it: M (3 x 3, triplet),
// H (3 x 2, CSC), q, b, mu.
const std::string kGlobal =
    "2\n1\n"
    "2\n3\n3\n1\nCSparse Version 3.1.9, May 4, 2016.  Copyright (c) Timothy A. Davis, 2006-2016\n"
    "triplet: 3-by-3, nzmax: 3 nnz: 3\n    0 0 : 1\n    1 1 : 1\n    2 2 : 0.5\n"
    "2\n3\n2\n2\nCSparse Version 3.1.9, May 4, 2016.  Copyright (c) Timothy A. Davis, 2006-2016\n"
    "3-by-2, nzmax: 2 nnz: 2, 1-norm: 1\n    col 0 : locations 0 to 0\n      1 : 1\n"
    "    col 1 : locations 1 to 1\n      0 : 1\n"
    "0 -1 0\n0 0\n0.5\n";

void ExpectGlobalRefused(const std::string& text, const std::string& sizes) {
  try {
    ParseSiconosProblem(text, "g.dat");
    ADD_FAILURE() << "a global-form problem was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3) << e.what();  // where M begins
    EXPECT_EQ(std::string(e.what()).rfind(
                  "g.dat:3: global-form friction-contact problem (M, H, q, b)", 0),
              0u)
        << e.what();
    EXPECT_NE(e.message().find(sizes), std::string::npos) << e.what();
    EXPECT_NE(e.message().find("use the local form"), std::string::npos) << e.what();
  }
}

TEST(SiconosCollection, GlobalFormIsRefusedByName) {
  ExpectGlobalRefused(kGlobal, "M is 3 x 3, H (line 12) is 3 x 2, 1 contacts");
  // With no contacts (gfc2d_granularflowonwall_00000_00117.dat has none) as well.
  ExpectGlobalRefused("2\n0\n0\n1\n1\n1 1\n2\n0\n1\n0\n0\n",
                      "M is 1 x 1, H (line 8) is 1 x 0, 0 contacts");
  // And where M happens to be 2nc x 2nc, so that the start reads as a local problem.
  ExpectGlobalRefused("2\n1\n0\n2\n2\n2 2\n1 0\n0 1\n0\n2\n2\n2 2\n1 0\n0 1\n0 -1\n0 0\n0.5\n",
                      "M is 2 x 2, H (line 9) is 2 x 2");
  // Local problems that fail for other reasons keep their own messages.
  try {
    ParseSiconosProblem("2\n0\n", "none.dat");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(e.message().find("number of contacts"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace unjam
