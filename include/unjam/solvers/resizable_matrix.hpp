// A dense matrix that gains and loses one row or column at a time: the rate path's
// systems and their updated QR (givens_qr.hpp) change by one unknown per event. Its
// storage only grows (geometrically), so an event edits in place; resizing an
// Eigen::MatrixXd instead reallocates and copies the whole matrix (measured: a third of a
// long path's time at 800 unknowns).
#pragma once

#include <algorithm>

#include <Eigen/Core>

namespace unjam {

class ResizableMatrix {
 public:
  using View = Eigen::Block<Eigen::MatrixXd>;
  using ConstView = Eigen::Block<const Eigen::MatrixXd>;

  Eigen::Index rows() const { return rows_; }
  Eigen::Index cols() const { return cols_; }
  View view() { return storage_.topLeftCorner(rows_, cols_); }
  ConstView view() const { return storage_.topLeftCorner(rows_, cols_); }

  // The entries inside both the old and the new size keep their values; new ones are
  // unspecified.
  void Resize(Eigen::Index rows, Eigen::Index cols) {
    if (rows > storage_.rows() || cols > storage_.cols()) {
      Eigen::MatrixXd grown(std::max(rows, Grown(storage_.rows())),
                            std::max(cols, Grown(storage_.cols())));
      const Eigen::Index r = std::min(rows, rows_), c = std::min(cols, cols_);
      grown.topLeftCorner(r, c) = storage_.topLeftCorner(r, c);
      storage_.swap(grown);
    }
    rows_ = rows;
    cols_ = cols;
  }
  template <class Derived>
  void Assign(const Eigen::MatrixBase<Derived>& a) {
    Resize(a.rows(), a.cols());
    view() = a;
  }

  // The rows (columns) after k move up (left) by one.
  void DropRow(Eigen::Index k) {
    const Eigen::Index below = rows_ - k - 1;
    for (Eigen::Index j = 0; j < cols_ && below > 0; ++j) {
      double* column = storage_.col(j).data();
      std::copy(column + k + 1, column + rows_, column + k);
    }
    --rows_;
  }
  void DropColumn(Eigen::Index k) {
    for (Eigen::Index j = k; j + 1 < cols_; ++j)
      storage_.col(j).head(rows_) = storage_.col(j + 1).head(rows_);
    --cols_;
  }

 private:
  static Eigen::Index Grown(Eigen::Index n) { return std::max<Eigen::Index>(8, n + n / 2); }

  Eigen::MatrixXd storage_;
  Eigen::Index rows_ = 0, cols_ = 0;
};

}  // namespace unjam
