// The contact problem in Delassus form (the Siconos form), for problems that come without
// bodies: stored problems of other codes (io/siconos_problem.hpp) and exported packings.
//
//   ũ = W r + q,   contact k owns rows 2k (normal) and 2k+1 (tangent),
//
// with the same contact laws as a ContactProblem (contact_problem.hpp): Signorini–Coulomb
// on (ũ_n, u_t) for a unilateral contact, ũ_n = 0 and r_t = 0 for a held (bilateral) one.
// There are always two unknowns per contact; a frictionless contact has μ = 0.
//
// W is read as given: symmetric and positive semidefinite for a mechanical problem, but
// neither is required. Backends that solve this form implement
// ContactSolver::SolveDelassus (contact_solver.hpp); the others refuse it.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "unjam/problem/contact_problem.hpp"

namespace unjam {

// What a contact obeys, without its geometry.
struct ContactLaw {
  double mu = 0.0;
  ConstraintKind kind = ConstraintKind::kUnilateral;
};

struct DelassusProblem {
  Eigen::SparseMatrix<double> w;  // NumUnknowns() × NumUnknowns()
  Eigen::VectorXd q;              // NumUnknowns()
  std::vector<ContactLaw> laws;   // one per contact

  int NumContacts() const { return static_cast<int>(laws.size()); }
  int NumUnknowns() const { return 2 * NumContacts(); }
};

// The Delassus form of a body problem: W = H M⁻¹ Hᵀ and q = H v_free + offset, so that
// W r + q is the posed velocity of the body problem for the same impulses. A frictionless
// problem (one unknown per contact) becomes a two-unknown problem with μ = 0 whose tangent
// rows are the translational relative velocity t·(v_j − v_i) + bias_t: spins are not degrees
// of freedom without friction, so they are held fixed (zero inverse inertia). Its normal
// impulses solve the frictionless problem, and its r_t vanish. Pressure-bath problems couple every
// pair of contacts through the cell rate, so their W is dense in the normal rows.
DelassusProblem ToDelassusProblem(const ContactProblem& problem);

// Throws std::invalid_argument if the sizes of W, q and the laws disagree,
// or a friction coefficient is negative or not finite.
void Validate(const DelassusProblem& problem);

}  // namespace unjam
