#include "unjam/indeterminacy/least_norm.hpp"

#include <algorithm>

#include <Eigen/CholmodSupport>

namespace unjam {

struct LeastNormSolver::Factor {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
};

LeastNormSolver::LeastNormSolver(const Eigen::SparseMatrix<double>& g, double relative_ridge)
    : g_(g), factor_(std::make_unique<Factor>()) {
  Eigen::SparseMatrix<double> normal = g_ * g_.transpose();
  Eigen::SparseMatrix<double> ridge(normal.rows(), normal.cols());
  ridge.setIdentity();
  normal += relative_ridge * std::max(1.0, normal.diagonal().mean()) * ridge;
  factor_->llt.compute(normal);
}

LeastNormSolver::~LeastNormSolver() = default;

bool LeastNormSolver::ok() const { return factor_->llt.info() == Eigen::Success; }

Eigen::VectorXd LeastNormSolver::Solve(const Eigen::VectorXd& r) const {
  return g_.transpose() * factor_->llt.solve(r);
}

}  // namespace unjam
