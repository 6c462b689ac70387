#include "unjam/problem/kinematic_admissibility.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <ClpSimplex.hpp>

#include "unjam/lp/lp_triplets.hpp"

namespace unjam {

namespace {

// The velocity scale of the step's prescriptions: the largest |offset| of a normal row.
double VelocityScale(const Eigen::VectorXd& offset, const ContactProblem& p) {
  double scale = 0.0;
  for (int k = 0; k < p.NumContacts(); ++k)
    scale = std::max(scale, std::abs(offset[k * p.UnknownsPerContact()]));
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
  lp::LpTriplets lp;
  lp.AddColumns(p.NumDofs(), -inf, inf);
  for (int k = 0; k < p.NumContacts(); ++k) {
    const int r = k * p.UnknownsPerContact();  // the normal row; tangential rows are free
    const double bound = -offset[r] / scale;
    const int row =
        lp.AddRow(bound, p.contacts[k].kind == ConstraintKind::kBilateral ? bound : inf);
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(h, r); it; ++it) {
      lp.Add(row, static_cast<int>(it.col()), it.value());
    }
  }
  ClpSimplex model;
  lp::LoadIntoClp(lp, model);
  // The primal tolerance only. The dual one stays CLP's default (1e-7), though the LP has
  // no objective: at 1e-9 the dual simplex found opening 378–463 of the frictionless
  // packing at fixed volume admissible, which it calls blocked with the default.
  model.setPrimalTolerance(1e-9);
  model.dual();
  switch (model.status()) {
    case 0: return out;
    case 1:
      out.admissible = false;
      out.message =
          "no motion satisfies the step's non-penetration (the kinematic LP is infeasible)";
      return out;
    default:
      out.decided = false;
      out.message = "the kinematic LP stopped with CLP status " + std::to_string(model.status());
      return out;
  }
}

}  // namespace unjam
