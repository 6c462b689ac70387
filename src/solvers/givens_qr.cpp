#include "unjam/solvers/givens_qr.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/QR>

#include "unjam/solvers/matrix_edit.hpp"

namespace unjam {

namespace {

struct Rotation {
  double c = 1.0, s = 0.0;
};
// The rotation [c s; −s c] that takes (a, b) to (hypot(a, b), 0).
Rotation RotationFor(double a, double b) {
  const double h = std::hypot(a, b);
  if (h == 0.0) return {};
  return {a / h, b / h};
}

// x ← c x + s y, y ← −s x + c y.
template <class X, class Y>
void Rotate(X&& x, Y&& y, const Rotation& g) {
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    const double xk = x[k], yk = y[k];
    x[k] = g.c * xk + g.s * yk;
    y[k] = -g.s * xk + g.c * yk;
  }
}

}  // namespace

void GivensQr::Reset(Eigen::Index rows) {
  q_ = Eigen::MatrixXd::Identity(rows, rows);
  r_ = Eigen::MatrixXd(rows, 0);
}

void GivensQr::Factorize(const Eigen::MatrixXd& a) {
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
  q_ = qr.householderQ() * Eigen::MatrixXd::Identity(a.rows(), a.rows());
  r_ = qr.matrixQR().triangularView<Eigen::Upper>();
}

void GivensQr::ZeroWithRows(Eigen::Index i, Eigen::Index j, Eigen::Index col, Eigen::Index from) {
  const Rotation g = RotationFor(r_(i, col), r_(j, col));
  const Eigen::Index n = r_.cols() - from;
  Rotate(r_.row(i).tail(n), r_.row(j).tail(n), g);
  r_(j, col) = 0.0;
  Rotate(q_.col(i), q_.col(j), g);
}

void GivensQr::AppendRow(const Eigen::VectorXd& row) {
  const Eigen::Index n = q_.rows(), c = r_.cols();
  q_.conservativeResize(n + 1, n + 1);
  q_.row(n).setZero();
  q_.col(n).setZero();
  q_(n, n) = 1.0;
  r_.conservativeResize(n + 1, Eigen::NoChange);
  r_.row(n) = row.transpose();
  // The new row against each diagonal entry in turn (rows past the columns are zero).
  for (Eigen::Index j = 0; j < std::min(c, n); ++j) ZeroWithRows(j, n, j, j);
}

void GivensQr::AppendColumn(const Eigen::VectorXd& column) {
  const Eigen::Index n = q_.rows(), c = r_.cols();
  Eigen::VectorXd w = q_.transpose() * column;
  // Zero w below row c from the bottom up; the other columns of R are zero there.
  for (Eigen::Index i = n - 1; i > c; --i) {
    const Rotation g = RotationFor(w[i - 1], w[i]);
    w[i - 1] = std::hypot(w[i - 1], w[i]);
    w[i] = 0.0;
    Rotate(q_.col(i - 1), q_.col(i), g);
  }
  r_.conservativeResize(Eigen::NoChange, c + 1);
  r_.col(c) = w;
}

void GivensQr::RemoveColumn(Eigen::Index k) {
  DropColumn(r_, k);
  // R is now upper Hessenberg from column k on: one rotation per column restores it.
  for (Eigen::Index j = k; j < r_.cols(); ++j) ZeroWithRows(j, j + 1, j, j);
}

void GivensQr::RemoveRow(Eigen::Index k) {
  const Eigen::Index n = q_.rows();
  // Rotate Q's row k into ±e₀ from the right, bottom up; R turns upper Hessenberg, and
  // without its first row it is the factor of A without row k.
  for (Eigen::Index i = n - 1; i > 0; --i) {
    const Rotation g = RotationFor(q_(k, i - 1), q_(k, i));
    Rotate(q_.col(i - 1), q_.col(i), g);
    q_(k, i) = 0.0;
    Rotate(r_.row(i - 1), r_.row(i), g);
  }
  DropRow(q_, k);
  DropColumn(q_, 0);
  DropRow(r_, 0);
}

double GivensQr::DiagonalRatio() const {
  const Eigen::Index c = std::min(r_.rows(), r_.cols());
  if (c == 0) return 1.0;
  const Eigen::VectorXd d = r_.diagonal().head(c).cwiseAbs();
  const double largest = d.maxCoeff();
  return largest > 0.0 ? d.minCoeff() / largest : 0.0;
}

}  // namespace unjam
