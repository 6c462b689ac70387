// Deleting one row or column of a dense matrix in place (the rows or columns after it move
// up by one): the rate path's systems and their updated QR (givens_qr.hpp) lose one unknown
// per event this way.
#pragma once

#include <Eigen/Core>

namespace unjam {

inline void DropRow(Eigen::MatrixXd& a, Eigen::Index k) {
  const Eigen::Index below = a.rows() - k - 1;
  if (below > 0) a.middleRows(k, below) = a.bottomRows(below).eval();
  a.conservativeResize(a.rows() - 1, Eigen::NoChange);
}

inline void DropColumn(Eigen::MatrixXd& a, Eigen::Index k) {
  const Eigen::Index right = a.cols() - k - 1;
  if (right > 0) a.middleCols(k, right) = a.rightCols(right).eval();
  a.conservativeResize(Eigen::NoChange, a.cols() - 1);
}

}  // namespace unjam
