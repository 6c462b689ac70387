#include "unjam/solvers/givens_qr.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/QR>

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
  q_.Assign(Eigen::MatrixXd::Identity(rows, rows));
  r_.Resize(rows, 0);
}

void GivensQr::Factorize(const Eigen::MatrixXd& a) {
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
  q_.Assign(qr.householderQ() * Eigen::MatrixXd::Identity(a.rows(), a.rows()));
  r_.Assign(qr.matrixQR().triangularView<Eigen::Upper>().toDenseMatrix());
}

void GivensQr::ZeroWithRows(Eigen::Index i, Eigen::Index j, Eigen::Index col, Eigen::Index from) {
  auto r = r_.view();
  auto q = q_.view();
  const Rotation g = RotationFor(r(i, col), r(j, col));
  const Eigen::Index n = r.cols() - from;
  Rotate(r.row(i).tail(n), r.row(j).tail(n), g);
  r(j, col) = 0.0;
  Rotate(q.col(i), q.col(j), g);
}

void GivensQr::AppendRow(const Eigen::VectorXd& row) {
  const Eigen::Index n = q_.rows(), c = r_.cols();
  q_.Resize(n + 1, n + 1);
  auto q = q_.view();
  q.row(n).setZero();
  q.col(n).setZero();
  q(n, n) = 1.0;
  r_.Resize(n + 1, c);
  r_.view().row(n) = row.transpose();
  // The new row against each diagonal entry in turn (rows past the columns are zero).
  for (Eigen::Index j = 0; j < std::min(c, n); ++j) ZeroWithRows(j, n, j, j);
}

void GivensQr::AppendColumn(const Eigen::VectorXd& column) {
  const Eigen::Index n = q_.rows(), c = r_.cols();
  auto q = q_.view();
  Eigen::VectorXd w = q.transpose() * column;
  // Zero w below row c from the bottom up; the other columns of R are zero there.
  for (Eigen::Index i = n - 1; i > c; --i) {
    const Rotation g = RotationFor(w[i - 1], w[i]);
    w[i - 1] = std::hypot(w[i - 1], w[i]);
    w[i] = 0.0;
    Rotate(q.col(i - 1), q.col(i), g);
  }
  r_.Resize(n, c + 1);
  r_.view().col(c) = w;
}

void GivensQr::RemoveColumn(Eigen::Index k) {
  r_.DropColumn(k);
  // R is now upper Hessenberg from column k on: one rotation per column restores it.
  for (Eigen::Index j = k; j < r_.cols(); ++j) ZeroWithRows(j, j + 1, j, j);
}

void GivensQr::RemoveRow(Eigen::Index k) {
  const Eigen::Index n = q_.rows();
  auto q = q_.view();
  auto r = r_.view();
  // Rotate Q's row k into ±e₀ from the right, bottom up; R turns upper Hessenberg, and
  // without its first row it is the factor of A without row k.
  for (Eigen::Index i = n - 1; i > 0; --i) {
    const Rotation g = RotationFor(q(k, i - 1), q(k, i));
    Rotate(q.col(i - 1), q.col(i), g);
    q(k, i) = 0.0;
    Rotate(r.row(i - 1), r.row(i), g);
  }
  q_.DropRow(k);
  q_.DropColumn(0);
  r_.DropRow(0);
}

double GivensQr::DiagonalRatio() const {
  const Eigen::Index c = std::min(r_.rows(), r_.cols());
  if (c == 0) return 1.0;
  const Eigen::VectorXd d = r_.view().diagonal().head(c).cwiseAbs();
  const double largest = d.maxCoeff();
  return largest > 0.0 ? d.minCoeff() / largest : 0.0;
}

}  // namespace unjam
