#include "unjam/indeterminacy/least_norm.hpp"

#include <algorithm>
#include <vector>

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>

namespace unjam {

namespace {

std::vector<int> DenseColumns(const Eigen::SparseMatrix<double>& g, int threshold) {
  std::vector<int> dense;
  for (int c = 0; c < g.outerSize(); ++c) {
    if (g.col(c).nonZeros() >= threshold) dense.push_back(c);
  }
  return dense;
}

}  // namespace

// (G Gᵀ + ε I) = S + U Uᵀ with S = G_s G_sᵀ + ε I (G without its dense columns U):
// (S + U Uᵀ)⁻¹ r = S⁻¹ r − S⁻¹ U (I + Uᵀ S⁻¹ U)⁻¹ Uᵀ S⁻¹ r.
struct LeastNormSolver::Factor {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
  Eigen::MatrixXd dense;                             // U
  Eigen::MatrixXd solved_dense;                      // S⁻¹ U
  Eigen::PartialPivLU<Eigen::MatrixXd> capacitance;  // I + Uᵀ S⁻¹ U
};

LeastNormSolver::LeastNormSolver(const Eigen::SparseMatrix<double>& g, double relative_ridge,
                                 int dense_column)
    : g_(g), factor_(std::make_unique<Factor>()) {
  const std::vector<int> dense = DenseColumns(g_, dense_column);
  Eigen::SparseMatrix<double> sparse;  // G without its dense columns (only if it has some)
  if (!dense.empty()) {
    sparse = g_;
    factor_->dense.resize(g_.rows(), static_cast<Eigen::Index>(dense.size()));
    for (std::size_t k = 0; k < dense.size(); ++k) {
      factor_->dense.col(static_cast<Eigen::Index>(k)) = Eigen::VectorXd(g_.col(dense[k]));
      for (Eigen::SparseMatrix<double>::InnerIterator it(sparse, dense[k]); it; ++it)
        it.valueRef() = 0.0;
    }
    sparse.prune(0.0);
  }
  const Eigen::SparseMatrix<double>& factorised = dense.empty() ? g_ : sparse;
  Eigen::SparseMatrix<double> normal = factorised * factorised.transpose();
  // The ridge is sized on the whole G Gᵀ, whose diagonal holds the rows' squared norms.
  const double mean_diagonal = dense.empty()
                                   ? normal.diagonal().mean()
                                   : g_.cwiseAbs2().sum() / static_cast<double>(g_.rows());
  Eigen::SparseMatrix<double> ridge(normal.rows(), normal.cols());
  ridge.setIdentity();
  normal += relative_ridge * std::max(1.0, mean_diagonal) * ridge;
  factor_->llt.compute(normal);
  if (dense.empty() || factor_->llt.info() != Eigen::Success) return;
  factor_->solved_dense = factor_->llt.solve(factor_->dense);
  const Eigen::Index k = factor_->dense.cols();
  factor_->capacitance.compute(Eigen::MatrixXd::Identity(k, k) +
                               factor_->dense.transpose() * factor_->solved_dense);
}

LeastNormSolver::~LeastNormSolver() = default;

bool LeastNormSolver::ok() const { return factor_->llt.info() == Eigen::Success; }

Eigen::VectorXd LeastNormSolver::Solve(const Eigen::VectorXd& r) const {
  Eigen::VectorXd y = factor_->llt.solve(r);
  if (factor_->dense.cols() > 0) {
    y -= factor_->solved_dense * factor_->capacitance.solve(factor_->dense.transpose() * y);
  }
  return g_.transpose() * y;
}

}  // namespace unjam
