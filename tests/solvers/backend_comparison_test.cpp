// CompareBackends: one run per (problem, backend, tolerance) in that order, residuals
// recomputed, distances to the reference, body and Delassus problems alike.
#include <gtest/gtest.h>

#include "../test_problems.hpp"
#include "unjam/solvers/backend_comparison.hpp"

namespace unjam {
namespace {

using testing::OneContact;
using testing::StackProblem;

TEST(BackendComparison, RunsEveryCombinationInOrderAndFindsTheUniqueForces) {
  std::vector<ComparisonProblem> problems;
  problems.push_back({"stack", StackProblem(4, 0.0), {}});  // frictionless: unique
  problems.push_back({"slide (W form)", ToDelassusProblem(OneContact(1.0, 3.0, 0.5)), {}});
  ComparisonOptions o;
  o.backends = {"nsgs", "newton"};
  o.tolerances = {1e-6, 1e-12};
  std::vector<ComparisonRun> runs;
  const auto refs =
      CompareBackends(problems, o, [&](const ComparisonRun& r) { runs.push_back(r); });
  ASSERT_EQ(refs.size(), 2u);
  ASSERT_EQ(runs.size(), 8u);
  EXPECT_EQ(runs[0].problem, "stack");
  EXPECT_EQ(runs[0].backend, "nsgs");
  EXPECT_EQ(runs[1].tolerance, 1e-12);
  EXPECT_EQ(runs[2].backend, "newton");
  EXPECT_EQ(runs[4].problem, "slide (W form)");
  for (const ComparisonRun& r : runs) {
    EXPECT_TRUE(r.report.converged()) << r.problem << " " << r.backend;
    EXPECT_LE(r.report.residual, r.tolerance);
    // Loose runs stop early, so their forces are only as close as their tolerance allows.
    EXPECT_LT(r.force_distance, r.tolerance == 1e-12 ? 1e-9 : 1e-3)
        << r.problem << " " << r.backend;
  }
  for (const ComparisonReference& ref : refs) EXPECT_LE(ref.residual, 1e-13);
}

TEST(BackendComparison, UnknownBackendIsRefusedBeforeAnyRun) {
  ComparisonOptions o;
  o.backends = {"nsgs", "no-such-backend"};
  o.tolerances = {1e-6};
  int runs = 0;
  EXPECT_THROW(CompareBackends({{"stack", StackProblem(2, 0.0), {}}}, o,
                               [&](const ComparisonRun&) { ++runs; }),
               std::invalid_argument);
  EXPECT_EQ(runs, 0);
}

}  // namespace
}  // namespace unjam
