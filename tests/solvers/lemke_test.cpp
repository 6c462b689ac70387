// The lemke backend: its pivoting core on LCPs with known answers (including a ray, which
// proves infeasibility), and on a frictional opening of the default packing, where the
// smooth backends stall: resolved to round-off, and its critical force inside the
// admissible interval of the independent linear program (issue 5's route).
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/lemke_mlcp.hpp"
#include "unjam/indeterminacy/force_bounds.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/perturbation.hpp"

namespace unjam {
namespace {

using lemke_internal::LemkeOutcome;
using lemke_internal::Mlcp;
using lemke_internal::SolveMlcp;

Eigen::SparseMatrix<double> Dense(int rows, int cols, std::initializer_list<double> values) {
  Eigen::MatrixXd m(rows, cols);
  auto it = values.begin();
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) m(r, c) = *it++;
  }
  return m.sparseView();
}

// A plain LCP w = M z + q (no free variables).
Mlcp Lcp(Eigen::SparseMatrix<double> m, Eigen::VectorXd q) {
  Mlcp p;
  const int n = static_cast<int>(q.size());
  p.p.resize(0, n);
  p.x0.resize(0);
  p.d.resize(n, 0);
  p.e_matrix = std::move(m);
  p.e = std::move(q);
  return p;
}

TEST(LemkeCore, SolvesASymmetricPositiveDefiniteLcp) {
  // Both z > 0: z = M⁻¹(5, 6) = (4/3, 7/3), w = 0.
  const auto r = SolveMlcp(Lcp(Dense(2, 2, {2, 1, 1, 2}), Eigen::Vector2d(-5, -6)), 100, 1e-16);
  ASSERT_EQ(r.outcome, LemkeOutcome::kSolved) << r.message;
  EXPECT_NEAR(r.z[0], 4.0 / 3.0, 1e-14);
  EXPECT_NEAR(r.z[1], 7.0 / 3.0, 1e-14);
}

TEST(LemkeCore, KeepsAComponentAtZeroWhenItsSlackIsPositive) {
  // z₁ alone: 2 z₁ − 2 = 0, then w₂ = z₁ + 3 > 0.
  const auto r = SolveMlcp(Lcp(Dense(2, 2, {2, 1, 1, 2}), Eigen::Vector2d(-2, 3)), 100, 1e-16);
  ASSERT_EQ(r.outcome, LemkeOutcome::kSolved) << r.message;
  EXPECT_NEAR(r.z[0], 1.0, 1e-15);
  EXPECT_EQ(r.z[1], 0.0);
}

TEST(LemkeCore, DegenerateTiesAreResolved) {
  // Three identical rows reach zero together at every step.
  const auto r = SolveMlcp(
      Lcp(Dense(3, 3, {1, 0, 0, 0, 1, 0, 0, 0, 1}), Eigen::Vector3d(-1, -1, -1)), 100, 1e-16);
  ASSERT_EQ(r.outcome, LemkeOutcome::kSolved) << r.message;
  EXPECT_NEAR((r.z - Eigen::Vector3d::Ones()).norm(), 0.0, 1e-15);
}

TEST(LemkeCore, EndsOnARayWhenNoSolutionExists) {
  // w = −z − 1 ≥ 0 with z ≥ 0 is impossible: no blocking row once z enters.
  const auto r = SolveMlcp(Lcp(Dense(1, 1, {-1}), Eigen::VectorXd::Constant(1, -1.0)), 100, 1e-16);
  EXPECT_EQ(r.outcome, LemkeOutcome::kRay);
}

TEST(LemkePerturbed, ThePolishSolvesTheFinalBasisForTheGivenProblem) {
  // w = M z + q with q = (−1, 0): degenerate (w₂ = 0 at z = 0). Followed for q + (1e-3, 2e-3),
  // the path ends on the basis (z₁, w₂); without the perturbation that basis gives
  // z = (0.5, 0), w₂ = 0.5 · 1 + 0 = 0.5 exactly, not the perturbed values.
  Mlcp p = Lcp(Dense(2, 2, {2, 0, 1, 1}), Eigen::Vector2d(-1, 0));
  p.perturbation = Eigen::Vector2d(1e-3, 2e-3);
  const auto r = SolveMlcp(p, 100, 1e-16);
  ASSERT_EQ(r.outcome, LemkeOutcome::kSolved) << r.message;
  EXPECT_NEAR(r.z[0], 0.5, 1e-15);
  EXPECT_EQ(r.z[1], 0.0);
  EXPECT_EQ(r.polish_violation, 0.0);
}

TEST(LemkePerturbed, ABasisThatOnlyThePerturbationMadeFeasibleIsReported) {
  // w = z − 1e-7 needs z = 1e-7; with the perturbation 1e-6 the path stops at once on the
  // basis (w) (w = 9e-7 ≥ 0), which without it has w = −1e-7: reported, not hidden.
  Mlcp p = Lcp(Dense(1, 1, {1}), Eigen::VectorXd::Constant(1, -1e-7));
  p.perturbation = Eigen::VectorXd::Constant(1, 1e-6);
  const auto r = SolveMlcp(p, 100, 1e-16);
  ASSERT_EQ(r.outcome, LemkeOutcome::kSolved) << r.message;
  EXPECT_EQ(r.z[0], 0.0);
  EXPECT_NEAR(r.polish_violation, 1e-7, 1e-20);
}

// A given basis (Mlcp::given_basis): the basis of an answer, carried to a nearby problem
// and solved as it is. It gives that problem's solution where it stays feasible (both
// components of the SPD example, for a right-hand side twice as large), reports by how
// much it is infeasible elsewhere, and a singular one is an error.
TEST(LemkeGivenBasis, SolvesANearbyProblemOnTheSameBasisWithoutAPivot) {
  Mlcp p = Lcp(Dense(2, 2, {2, 1, 1, 2}), Eigen::Vector2d(-10, -12));
  p.given_basis = {1, 1};
  const auto r = SolveMlcp(p, 100, 1e-16);
  ASSERT_EQ(r.outcome, LemkeOutcome::kSolved) << r.message;
  EXPECT_EQ(r.pivots, 0);
  EXPECT_NEAR(r.z[0], 8.0 / 3.0, 1e-14);
  EXPECT_NEAR(r.z[1], 14.0 / 3.0, 1e-14);
  EXPECT_EQ(r.polish_violation, 0.0);
  EXPECT_EQ(r.z_basic, std::vector<char>({1, 1}));
}

TEST(LemkeGivenBasis, AnInfeasibleBasisIsReportedNotHidden) {
  // On q = (−2, 3) the basis (z₁, z₂) gives z = M⁻¹(2, −3) = (7/3, −8/3); the solution is
  // (1, 0) on the basis (z₁, w₂), which a path finds.
  Mlcp p = Lcp(Dense(2, 2, {2, 1, 1, 2}), Eigen::Vector2d(-2, 3));
  p.given_basis = {1, 1};
  const auto r = SolveMlcp(p, 100, 1e-16);
  ASSERT_EQ(r.outcome, LemkeOutcome::kSolved) << r.message;
  EXPECT_NEAR(r.polish_violation, 8.0 / 3.0, 1e-14);
  EXPECT_EQ(r.z[1], 0.0);
  p.given_basis.clear();
  const auto path = SolveMlcp(p, 100, 1e-16);
  EXPECT_NEAR(path.z[0], 1.0, 1e-15);
  EXPECT_EQ(path.z_basic, std::vector<char>({1, 0}));
}

TEST(LemkeGivenBasis, ASingularBasisIsAnError) {
  // Two identical contacts hold one free velocity: both impulses basic is singular.
  Mlcp p;
  p.p = Dense(1, 2, {1, 1});
  p.x0 = Eigen::VectorXd::Constant(1, -1.0);
  p.d = Dense(2, 1, {1, 1});
  p.e_matrix = Dense(2, 2, {0, 0, 0, 0});
  p.e = Eigen::Vector2d::Zero();
  p.given_basis = {1, 1};
  EXPECT_EQ(SolveMlcp(p, 100, 1e-16).outcome, LemkeOutcome::kSingularBasis);
}

TEST(LemkeCore, FreeVariablesStayBasic) {
  // x − z = 0 and w = x − 1: the LCP w = z − 1, so z = 1 and x = 1.
  Mlcp p;
  p.p = Dense(1, 1, {1});
  p.x0 = Eigen::VectorXd::Zero(1);
  p.d = Dense(1, 1, {1});
  p.e_matrix.resize(1, 1);
  p.e = Eigen::VectorXd::Constant(1, -1.0);
  const auto r = SolveMlcp(p, 100, 1e-16);
  ASSERT_EQ(r.outcome, LemkeOutcome::kSolved) << r.message;
  EXPECT_NEAR(r.z[0], 1.0, 1e-15);
  EXPECT_NEAR(r.x[0], 1.0, 1e-15);
}

TEST(LemkeBackend, FrictionalOpeningIsResolvedAndInsideTheAdmissibleInterval) {
  // Contact 49–208 of the default packing (μ = 0.5): newton stalls near 1e-11 on it
  // (docs/backends.md). Lemke resolves it to round-off; the response is quasi-static and its
  // F_crit lies in the LP interval [min, max without friction] of the same contact.
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.5.unjam");
  PerturbationOptions o;
  o.backend = "lemke";
  const PerturbationBase base = PreparePerturbations(scene, o);
  PerturbationTarget target;
  for (const PerturbationTarget& t : ContactTargets(base)) {
    if (t.i == 49 && t.j == 208) target = t;
  }
  ASSERT_EQ(target.i, 49);
  const PerturbationResult r = Perturb(base, target, o);
  ASSERT_TRUE(r.solve.converged()) << r.solve.message;
  EXPECT_LT(r.solve.residual, 1e-13);
  ASSERT_EQ(r.status, PerturbationStatus::kOk);

  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  int k = -1;
  for (int c = 0; c < static_cast<int>(s.contacts.size()); ++c) {
    if (s.contacts[c].i == 49 && s.contacts[c].j == 208) k = c;
  }
  ASSERT_GE(k, 0);
  const BoundsReport b = ComputeForceBounds(s, {k}, {});
  ASSERT_TRUE(b.bounds[0].min.ok() && b.bounds[0].max_without_friction.ok());
  EXPECT_GE(r.f_crit, b.bounds[0].min.value - 1e-8);
  EXPECT_LE(r.f_crit, b.bounds[0].max_without_friction.value + 1e-8);
}

}  // namespace
}  // namespace unjam
