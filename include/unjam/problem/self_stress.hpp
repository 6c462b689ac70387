// The self-stresses of a contact network: impulses s with Hᵀ s = 0, which load no body
// (H the contact Jacobian of contact_problem.hpp, rows per contact (n[, t])). They are the
// directions in which the forces of a static hyperstatic packing are indeterminate
// (docs/indeterminacy.md): every admissible network is the static one plus a self-stress.
// Their number is the degree of indeterminacy, small next to the number of contacts (33 of
// 1 288 force components at N = 500, 302 of 7 718 at N = 3000), so a problem over forces
// posed in their coordinates is small and dense (solvers/rate_path.hpp).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace unjam {

struct SelfStressBasis {
  // Orthonormal columns spanning ker Hᵀ: H.rows() × dimension.
  Eigen::MatrixXd basis;
  int rank = 0;            // of H, as SuiteSparseQR found it
  double tolerance = 0.0;  // its rank tolerance: 1e-10 × the largest column norm of H
  // max_j ‖Hᵀ s_j‖ / ‖H‖ (‖H‖ the largest column norm): how well the columns are self-stresses.
  double max_violation = 0.0;
  int dimension() const { return static_cast<int>(basis.cols()); }
};

// Rank-revealing sparse QR of H (SuiteSparseQR): H P = Q R, and ker Hᵀ is spanned by the
// columns of Q beyond the rank. A column whose ‖Hᵀ s‖ exceeds the rank tolerance (a
// dependency that the rank estimate missed counts as independent, and its column is
// no self-stress) is dropped.
SelfStressBasis ComputeSelfStresses(const Eigen::SparseMatrix<double>& h);

// The self-stresses once the balance of some degrees of freedom is no longer required
// (their columns of H released: a particle moved by a prescribed motion, a frozen cell):
// `basis` extended by the least-norm impulses z with Hᵀz = e_d for each released column d,
// orthonormalised (range(H) is orthogonal to ker Hᵀ, so the old columns stay as they are).
// A released column that H does not reach (a floppy degree of freedom) adds nothing.
Eigen::MatrixXd ExtendSelfStresses(const Eigen::MatrixXd& basis,
                                   const Eigen::SparseMatrix<double>& h,
                                   const std::vector<int>& released_columns);

}  // namespace unjam
