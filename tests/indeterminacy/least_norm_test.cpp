// The least-norm solver with a dense column (taken out by the Woodbury identity) against the
// plain factorisation of G Gᵀ on the same system.
#include "unjam/indeterminacy/least_norm.hpp"

#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace unjam {
namespace {

// A contact-closure-like G: each row couples two of `columns` particle columns, and the last
// column (a cell strain) enters every row.
Eigen::SparseMatrix<double> ClosureLikeMatrix(int rows, int columns) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> pick(0, columns - 2);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  for (int r = 0; r < rows; ++r) {
    const int a = pick(rng);
    int b = pick(rng);
    if (b == a) b = (a + 1) % (columns - 1);
    t.emplace_back(r, a, value(rng));
    t.emplace_back(r, b, value(rng));
    t.emplace_back(r, columns - 1, 1.0 + value(rng));
  }
  Eigen::SparseMatrix<double> g(rows, columns);
  g.setFromTriplets(t.begin(), t.end());
  return g;
}

TEST(LeastNorm, TheDenseColumnByWoodburyGivesThePlainFactorisationsSolution) {
  const Eigen::SparseMatrix<double> g = ClosureLikeMatrix(300, 500);
  const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(300, -1.0, 2.0);
  const LeastNormSolver plain(g, 1e-14, /*dense_column=*/1000000);
  const LeastNormSolver woodbury(g, 1e-14, /*dense_column=*/100);
  ASSERT_TRUE(plain.ok());
  ASSERT_TRUE(woodbury.ok());
  const Eigen::VectorXd x_plain = plain.Solve(r);
  const Eigen::VectorXd x_woodbury = woodbury.Solve(r);
  // Both solve G x = r as far as the ridge lets them (the random G is poorly conditioned).
  const double plain_miss = (g * x_plain - r).lpNorm<Eigen::Infinity>();
  EXPECT_LT(plain_miss, 1e-8);
  // The same bound for both (the misses are round-off through the ridge, and which one is
  // smaller depends on the BLAS: OpenBLAS gave 8.4e-10 against 6.6e-10).
  EXPECT_LT((g * x_woodbury - r).lpNorm<Eigen::Infinity>(), 1e-8);
  EXPECT_LT((x_woodbury - x_plain).lpNorm<Eigen::Infinity>(),
            1e-10 * x_plain.lpNorm<Eigen::Infinity>());
}

TEST(LeastNorm, WithoutADenseColumnBothPathsAreTheSame) {
  Eigen::SparseMatrix<double> g = ClosureLikeMatrix(200, 400);
  g = g.leftCols(399);  // no cell column
  const Eigen::VectorXd r = Eigen::VectorXd::Ones(200);
  const LeastNormSolver a(g, 1e-14, 1000000);
  const LeastNormSolver b(g, 1e-14, 100);
  EXPECT_EQ(a.Solve(r), b.Solve(r));
}

}  // namespace
}  // namespace unjam
