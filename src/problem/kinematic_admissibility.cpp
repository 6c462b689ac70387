#include "unjam/problem/kinematic_admissibility.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <ClpSimplex.hpp>
#include <CoinPackedMatrix.hpp>

namespace unjam {

namespace {

// The velocity scale of the step's prescriptions: the largest |offset| of a normal row.
double VelocityScale(const Eigen::VectorXd& offset, const ContactProblem& p) {
  double scale = 0.0;
  for (int k = 0; k < p.NumContacts(); ++k) scale = std::max(scale, std::abs(offset[k * p.UnknownsPerContact()]));
  return scale;
}

}  // namespace

KinematicAdmissibility CheckKinematicAdmissibility(const ContactProblem& p) {
  KinematicAdmissibility out;
  if (p.NumContacts() == 0) return out;
  const Eigen::SparseMatrix<double, Eigen::RowMajor> h = AssembleJacobian(p);
  const Eigen::VectorXd offset = VelocityOffset(p);
  const double scale = VelocityScale(offset, p);
  if (scale == 0.0) return out;  // v = 0 satisfies every row
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<int> rows, cols;
  std::vector<double> values, row_lower, row_upper;
  for (int k = 0; k < p.NumContacts(); ++k) {
    const int r = k * p.UnknownsPerContact();  // the normal row; tangential rows are free
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(h, r); it; ++it) {
      rows.push_back(k);
      cols.push_back(static_cast<int>(it.col()));
      values.push_back(it.value());
    }
    const double bound = -offset[r] / scale;
    row_lower.push_back(bound);
    row_upper.push_back(p.contacts[k].kind == ConstraintKind::kBilateral ? bound : inf);
  }
  const int dofs = p.NumDofs();
  const std::vector<double> col_lower(dofs, -inf), col_upper(dofs, inf), objective(dofs, 0.0);
  CoinPackedMatrix matrix(true, rows.data(), cols.data(), values.data(), static_cast<CoinBigIndex>(values.size()));
  // Trailing rows or columns without entries (a contact between sides without degrees of
  // freedom, a body in no contact) are not implied by the triplets.
  matrix.setDimensions(p.NumContacts(), dofs);
  ClpSimplex model;
  model.setLogLevel(0);
  model.loadProblem(matrix, col_lower.data(), col_upper.data(), objective.data(), row_lower.data(), row_upper.data());
  model.setPrimalTolerance(1e-9);
  model.dual();
  switch (model.status()) {
    case 0: return out;
    case 1:
      out.admissible = false;
      out.message = "no motion satisfies the step's non-penetration (the kinematic LP is infeasible)";
      return out;
    default:
      out.decided = false;
      out.message = "the kinematic LP stopped with CLP status " + std::to_string(model.status());
      return out;
  }
}

}  // namespace unjam
