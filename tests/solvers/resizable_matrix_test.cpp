#include "unjam/solvers/resizable_matrix.hpp"

#include <random>

#include <Eigen/Core>
#include <gtest/gtest.h>

namespace unjam {
namespace {

// Growth past its storage, appends and deletions anywhere: the same entries, bit for bit,
// as a plain matrix put through the same edits by copying.
TEST(ResizableMatrix, KeepsItsEntriesThroughGrowthAndDeletions) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  ResizableMatrix a;
  Eigen::MatrixXd reference(0, 0);
  for (int step = 0; step < 300; ++step) {
    const Eigen::Index rows = reference.rows(), cols = reference.cols();
    const int kind = static_cast<int>(rng() % 4);
    if (kind <= 1 || rows == 0 || cols == 0) {  // one more row and column
      a.Resize(rows + 1, cols + 1);
      Eigen::MatrixXd grown =
          Eigen::MatrixXd::NullaryExpr(rows + 1, cols + 1, [&] { return value(rng); });
      grown.topLeftCorner(rows, cols) = reference;
      a.view().row(rows) = grown.row(rows);
      a.view().col(cols) = grown.col(cols);
      reference = grown;
    } else if (kind == 2) {
      const Eigen::Index k = static_cast<Eigen::Index>(rng() % rows);
      a.DropRow(k);
      Eigen::MatrixXd b(rows - 1, cols);
      b << reference.topRows(k), reference.bottomRows(rows - k - 1);
      reference = b;
    } else {
      const Eigen::Index k = static_cast<Eigen::Index>(rng() % cols);
      a.DropColumn(k);
      Eigen::MatrixXd b(rows, cols - 1);
      b << reference.leftCols(k), reference.rightCols(cols - k - 1);
      reference = b;
    }
    ASSERT_EQ(a.rows(), reference.rows());
    ASSERT_EQ(a.cols(), reference.cols());
    ASSERT_TRUE(a.view() == reference) << "after step " << step;
  }
  EXPECT_GT(a.rows(), 40);  // grown through several reallocations of its storage
}

}  // namespace
}  // namespace unjam
