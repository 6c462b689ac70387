#include "unjam/solvers/givens_qr.hpp"

#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

namespace unjam {
namespace {

void ExpectFactorizes(const GivensQr& qr, const Eigen::MatrixXd& a) {
  ASSERT_EQ(qr.rows(), a.rows());
  ASSERT_EQ(qr.cols(), a.cols());
  const Eigen::MatrixXd& q = qr.q();
  const Eigen::MatrixXd& r = qr.r();
  EXPECT_LE((q * r - a).norm(), 1e-12 * (1.0 + a.norm()));
  EXPECT_LE((q.transpose() * q - Eigen::MatrixXd::Identity(q.rows(), q.cols())).norm(), 1e-12);
  for (Eigen::Index j = 0; j < r.cols(); ++j)
    for (Eigen::Index i = j + 1; i < r.rows(); ++i) EXPECT_EQ(r(i, j), 0.0) << i << "," << j;
}

Eigen::MatrixXd WithoutRow(const Eigen::MatrixXd& a, Eigen::Index k) {
  Eigen::MatrixXd b(a.rows() - 1, a.cols());
  b << a.topRows(k), a.bottomRows(a.rows() - k - 1);
  return b;
}

Eigen::MatrixXd WithoutColumn(const Eigen::MatrixXd& a, Eigen::Index k) {
  Eigen::MatrixXd b(a.rows(), a.cols() - 1);
  b << a.leftCols(k), a.rightCols(a.cols() - k - 1);
  return b;
}

// The way the rate path uses it: one more row than columns, and a variable (row) and an
// equation (column) added or removed together, hundreds of times; brute force (A itself)
// alongside.
TEST(GivensQr, UpdatesMatchTheMatrixOverALongRandomSequence) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  GivensQr qr;
  qr.Reset(1);
  Eigen::MatrixXd a(1, 0);
  for (int step = 0; step < 400; ++step) {
    const bool grow = a.cols() < 3 || (a.cols() < 40 && rng() % 3 != 0);
    if (grow) {
      Eigen::VectorXd row(a.cols());
      for (Eigen::Index j = 0; j < row.size(); ++j) row[j] = value(rng);
      qr.AppendRow(row);
      a.conservativeResize(a.rows() + 1, Eigen::NoChange);
      a.row(a.rows() - 1) = row.transpose();
      Eigen::VectorXd column(a.rows());
      for (Eigen::Index i = 0; i < column.size(); ++i) column[i] = value(rng);
      qr.AppendColumn(column);
      a.conservativeResize(Eigen::NoChange, a.cols() + 1);
      a.col(a.cols() - 1) = column;
    } else {
      const Eigen::Index k = static_cast<Eigen::Index>(rng() % static_cast<unsigned>(a.cols()));
      qr.RemoveColumn(k);
      a = WithoutColumn(a, k);
      qr.RemoveRow(k + 1);
      a = WithoutRow(a, k + 1);
    }
    ExpectFactorizes(qr, a);
    if (HasFailure()) FAIL() << "at step " << step;
  }
  // The kernel of Aᵀ is Q's last column.
  EXPECT_LE((a.transpose() * qr.q().col(qr.rows() - 1)).norm(), 1e-12);
}

TEST(GivensQr, FactorizeStartsOverAndTheDiagonalRatioSeesRankLoss) {
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(6, 5);
  GivensQr qr;
  qr.Factorize(a);
  ExpectFactorizes(qr, a);
  EXPECT_GT(qr.DiagonalRatio(), 1e-3);
  a.col(4) = a.col(0) - 2.0 * a.col(2);  // rank 4
  qr.Factorize(a);
  EXPECT_LT(qr.DiagonalRatio(), 1e-14);
}

}  // namespace
}  // namespace unjam
