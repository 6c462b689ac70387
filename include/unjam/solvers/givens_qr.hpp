// A QR factorisation A = Q R kept up to date by Givens rotations while rows and columns of
// A come and go, O(n²) per change instead of O(n³) for a new factorisation (Golub & Van
// Loan, "Matrix Computations", 4th ed., §6.5). The rate path (rate_path.hpp) needs the
// kernel of its piece's system, which changes by one unknown per event: with A the
// transpose of that system (one row per variable, one column per equation, one more row
// than columns), the kernel is Q's last column.
#pragma once

#include <Eigen/Core>

#include "unjam/solvers/resizable_matrix.hpp"

namespace unjam {

class GivensQr {
 public:
  GivensQr() { Reset(1); }
  // A with `rows` rows and no column: Q = I, R empty.
  void Reset(Eigen::Index rows);
  // A factorised anew (no pivoting): after many updates, to shed their round-off.
  void Factorize(const Eigen::MatrixXd& a);

  void AppendRow(const Eigen::VectorXd& row);        // one entry per column, the new last row
  void AppendColumn(const Eigen::VectorXd& column);  // one entry per row, the new last column
  void RemoveRow(Eigen::Index k);
  void RemoveColumn(Eigen::Index k);

  Eigen::Index rows() const { return q_.rows(); }
  Eigen::Index cols() const { return r_.cols(); }
  ResizableMatrix::ConstView q() const { return q_.view(); }
  ResizableMatrix::ConstView r() const { return r_.view(); }
  // min |R_jj| / max |R_jj| over the columns (1 without columns): a rank test without
  // pivoting, good enough to send doubtful cases to a pivoted factorisation.
  double DiagonalRatio() const;

 private:
  // Rotates rows i, j of R (from column `from` on) so that R(j, col) = 0, and Q's columns
  // i, j so that Q R stays A.
  void ZeroWithRows(Eigen::Index i, Eigen::Index j, Eigen::Index col, Eigen::Index from);

  ResizableMatrix q_, r_;
};

}  // namespace unjam
