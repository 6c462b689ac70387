// Least-norm solutions of underdetermined sparse systems G x = r, shared by the admissible-
// force projection and contact closure: x = Gᵀ (G Gᵀ + ε I)⁻¹ r, with G Gᵀ factorised once
// (sparse Cholesky, CHOLMOD) and solved for any number of right-hand sides. The ridge
// ε = relative_ridge · max(1, mean diagonal of G Gᵀ) keeps a rank-deficient G (a particle
// with too few contacts) factorisable; the caller checks the residual it gets.
#pragma once

#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace unjam {

class LeastNormSolver {
 public:
  LeastNormSolver(const Eigen::SparseMatrix<double>& g, double relative_ridge);
  ~LeastNormSolver();
  LeastNormSolver(const LeastNormSolver&) = delete;
  LeastNormSolver& operator=(const LeastNormSolver&) = delete;

  // False if the factorisation failed.
  bool ok() const;
  // Gᵀ (G Gᵀ + ε I)⁻¹ r.
  Eigen::VectorXd Solve(const Eigen::VectorXd& r) const;

 private:
  struct Factor;  // hides CHOLMOD from the public headers
  Eigen::SparseMatrix<double> g_;
  std::unique_ptr<Factor> factor_;
};

}  // namespace unjam
