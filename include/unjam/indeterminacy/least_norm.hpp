// Least-norm solutions of underdetermined sparse systems G x = r, shared by the admissible-
// force projection and contact closure: x = Gᵀ (G Gᵀ + ε I)⁻¹ r, with G Gᵀ factorised once
// (sparse Cholesky, CHOLMOD) and solved for any number of right-hand sides. The ridge
// ε = relative_ridge · max(1, mean diagonal of G Gᵀ) keeps a rank-deficient G (a particle
// with too few contacts) factorisable; the caller checks the residual it gets.
//
// A column with at least `dense_column` non-zeros (the cell strain's in contact closure,
// on which every contact's gap depends) would make G Gᵀ dense: such columns are taken out
// of the factorisation and put back by the Woodbury identity.
#pragma once

#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace unjam {

class LeastNormSolver {
 public:
  // A column this full goes to the Woodbury update. 1024 takes the cell column of an
  // N = 3000 closure (about 3 900 contacts) out of the factorisation of G Gᵀ, which it
  // would make dense: 18 s of a 126 s packing run, against 0.02 s through the update,
  // the packing bit for bit the same either way (docs/performance.md). The N = 500 closures
  // (under 1 000 contacts) keep the cell column in the factorisation.
  static constexpr int kDenseColumn = 1024;
  LeastNormSolver(const Eigen::SparseMatrix<double>& g, double relative_ridge,
                  int dense_column = kDenseColumn);
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
