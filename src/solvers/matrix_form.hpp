// A body or Delassus problem as the matrices of its step, for the backends that work on
// matrices (newton, lemke):
//     v = v_free + G r,   ũ = H v + offset,
// with G = M⁻¹Hᵀ for bodies. A Delassus problem (ũ = W r + q) is the same with H = I,
// G = W, v_free = q and no offset, so that v is ũ itself.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "unjam/problem/contact_problem.hpp"
#include "unjam/problem/delassus_problem.hpp"

namespace unjam::solvers_internal {

struct MatrixForm {
  int per_contact = 2;            // unknowns per contact
  Eigen::SparseMatrix<double> h;  // unknowns × dofs
  Eigen::SparseMatrix<double> g;  // dofs × unknowns: M⁻¹Hᵀ, or W
  Eigen::VectorXd v_free;
  Eigen::VectorXd offset;
  std::vector<ContactLaw> laws;

  int NumContacts() const { return static_cast<int>(laws.size()); }
  int NumUnknowns() const { return static_cast<int>(h.rows()); }
  int NumDofs() const { return static_cast<int>(h.cols()); }
};

inline MatrixForm MatrixFormOf(const ContactProblem& p) {
  MatrixForm m;
  m.per_contact = p.UnknownsPerContact();
  m.h = AssembleJacobian(p);
  m.g = InverseMassDiagonal(p).asDiagonal() * m.h.transpose();
  m.v_free = FreeVelocityVector(p);
  m.offset = VelocityOffset(p);
  for (const ProblemContact& c : p.contacts) m.laws.push_back({c.mu, c.kind});
  return m;
}

inline MatrixForm MatrixFormOf(const DelassusProblem& p) {
  MatrixForm m;
  m.h.resize(p.NumUnknowns(), p.NumUnknowns());
  m.h.setIdentity();
  m.g = p.w;
  m.v_free = p.q;
  m.offset = Eigen::VectorXd::Zero(p.NumUnknowns());
  m.laws = p.laws;
  return m;
}

}  // namespace unjam::solvers_internal
