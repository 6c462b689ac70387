#include "unjam/problem/self_stress.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <Eigen/CholmodSupport>
#include <SuiteSparseQR.hpp>

namespace unjam {

namespace {

double LargestColumnNorm(const Eigen::SparseMatrix<double>& a) {
  double largest = 0.0;
  for (int k = 0; k < a.outerSize(); ++k) largest = std::max(largest, a.col(k).norm());
  return largest;
}

// CHOLMOD's workspace, started and finished with its owner (long-index API, as SuiteSparseQR's).
struct Cholmod {
  cholmod_common cc;
  Cholmod() { cholmod_l_start(&cc); }
  ~Cholmod() { cholmod_l_finish(&cc); }
  Cholmod(const Cholmod&) = delete;
  Cholmod& operator=(const Cholmod&) = delete;
};

cholmod_sparse* ToCholmod(const Eigen::SparseMatrix<double>& a, cholmod_common* cc) {
  Eigen::SparseMatrix<double> compressed = a;
  compressed.makeCompressed();
  cholmod_sparse* m = cholmod_l_allocate_sparse(a.rows(), a.cols(), compressed.nonZeros(), 1, 1, 0,
                                                CHOLMOD_REAL, cc);
  auto* p = static_cast<SuiteSparse_long*>(m->p);
  auto* i = static_cast<SuiteSparse_long*>(m->i);
  auto* x = static_cast<double*>(m->x);
  for (Eigen::Index k = 0; k <= compressed.cols(); ++k) p[k] = compressed.outerIndexPtr()[k];
  for (Eigen::Index k = 0; k < compressed.nonZeros(); ++k) {
    i[k] = compressed.innerIndexPtr()[k];
    x[k] = compressed.valuePtr()[k];
  }
  return m;
}

// Q [0; I] of the QR factorisation: the columns of Q from `rank` on.
Eigen::MatrixXd TrailingColumnsOfQ(SuiteSparseQR_factorization<double>* qr, Eigen::Index rows,
                                   Eigen::Index rank, cholmod_common* cc) {
  const Eigen::Index count = rows - rank;
  cholmod_dense* x = cholmod_l_zeros(rows, count, CHOLMOD_REAL, cc);
  auto* xv = static_cast<double*>(x->x);
  for (Eigen::Index j = 0; j < count; ++j) xv[j * rows + rank + j] = 1.0;
  cholmod_dense* y = SuiteSparseQR_qmult<double>(SPQR_QX, qr, x, cc);
  Eigen::MatrixXd out = Eigen::Map<Eigen::MatrixXd>(static_cast<double*>(y->x), rows, count);
  cholmod_l_free_dense(&x, cc);
  cholmod_l_free_dense(&y, cc);
  return out;
}

}  // namespace

SelfStressBasis ComputeSelfStresses(const Eigen::SparseMatrix<double>& h) {
  SelfStressBasis out;
  const double norm = LargestColumnNorm(h);
  out.tolerance = 1e-10 * norm;
  if (h.rows() == 0) return out;
  if (h.nonZeros() == 0) {
    out.basis = Eigen::MatrixXd::Identity(h.rows(), h.rows());
    return out;
  }
  Cholmod cholmod;
  cholmod_sparse* a = ToCholmod(h, &cholmod.cc);
  SuiteSparseQR_factorization<double>* qr =
      SuiteSparseQR_factorize<double>(SPQR_ORDERING_DEFAULT, out.tolerance, a, &cholmod.cc);
  cholmod_l_free_sparse(&a, &cholmod.cc);
  if (qr == nullptr)
    throw std::runtime_error("SuiteSparseQR could not factorise the contact Jacobian");
  out.rank = static_cast<int>(qr->rank);
  const Eigen::MatrixXd candidates = TrailingColumnsOfQ(qr, h.rows(), qr->rank, &cholmod.cc);
  SuiteSparseQR_free<double>(&qr, &cholmod.cc);

  const Eigen::SparseMatrix<double> ht = h.transpose();
  std::vector<Eigen::Index> kept;
  for (Eigen::Index j = 0; j < candidates.cols(); ++j) {
    const double violation = (ht * candidates.col(j)).norm() / std::max(norm, 1e-300);
    if (violation <= 1e-8) {
      kept.push_back(j);
      out.max_violation = std::max(out.max_violation, violation);
    }
  }
  out.basis.resize(h.rows(), static_cast<Eigen::Index>(kept.size()));
  for (std::size_t k = 0; k < kept.size(); ++k)
    out.basis.col(static_cast<Eigen::Index>(k)) = candidates.col(kept[k]);
  return out;
}

Eigen::MatrixXd ExtendSelfStresses(const Eigen::MatrixXd& basis,
                                   const Eigen::SparseMatrix<double>& h,
                                   const std::vector<int>& released_columns) {
  if (released_columns.empty()) return basis;
  // z = H (HᵀH + εI)⁻¹ e_d: the least-norm impulses with Hᵀz = e_d; the ridge only keeps
  // floppy degrees of freedom (a rattler's) from making HᵀH singular.
  Eigen::SparseMatrix<double> normal = h.transpose() * h;
  const double ridge = 1e-12 * std::max(1.0, normal.diagonal().maxCoeff());
  for (Eigen::Index d = 0; d < normal.rows(); ++d) normal.coeffRef(d, d) += ridge;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> llt(normal);
  if (llt.info() != Eigen::Success) throw std::runtime_error("CHOLMOD could not factorise HᵀH");
  Eigen::MatrixXd extended(basis.rows(),
                           basis.cols() + static_cast<Eigen::Index>(released_columns.size()));
  extended.leftCols(basis.cols()) = basis;
  Eigen::Index count = basis.cols();
  for (int d : released_columns) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(h.cols());
    e[d] = 1.0;
    Eigen::VectorXd z = h * llt.solve(e);
    // Only the released balance may change: a column H cannot reach gives z ≈ 0.
    const double reach = (h.transpose() * z - e).norm();
    for (Eigen::Index j = basis.cols(); j < count; ++j)
      z -= extended.col(j).dot(z) * extended.col(j);
    const double length = z.norm();
    if (!(length > 1e-9) || reach > 1e-6) continue;
    extended.col(count++) = z / length;
  }
  return extended.leftCols(count);
}

}  // namespace unjam
