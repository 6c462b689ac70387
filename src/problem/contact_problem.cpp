// Sparse views of a ContactProblem and the maps r ↦ v ↦ ũ that every backend shares.
#include "unjam/problem/contact_problem.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/SparseCore>

namespace unjam {

namespace {

[[noreturn]] void RejectProblem(const std::string& what) {
  throw std::invalid_argument("contact problem: " + what);
}

std::string Indexed(const char* field, std::size_t k) {
  return std::string(field) + "[" + std::to_string(k) + "]";
}

void RequireSize(const char* field, std::size_t size, std::size_t expected, bool may_be_empty) {
  if (size == expected || (may_be_empty && size == 0)) return;
  RejectProblem(std::string(field) + " has " + std::to_string(size) + " entries, expected " +
                std::to_string(expected) + (may_be_empty ? " or 0" : ""));
}

void RequireFinite(const std::string& field, double value) {
  if (!std::isfinite(value)) RejectProblem(field + " is " + std::to_string(value) + ", not finite");
}

void RequireNonNegative(const std::string& field, double value) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    RejectProblem(field + " is " + std::to_string(value) + " (must be finite and >= 0)");
  }
}

void ValidateBodies(const ContactProblem& p) {
  const std::size_t n = p.inv_mass.size();
  RequireSize("free_velocity", p.free_velocity.size(), n, false);
  RequireSize("inv_inertia", p.inv_inertia.size(), n, !p.frictional);
  RequireSize("free_spin", p.free_spin.size(), n, !p.frictional);
  for (std::size_t b = 0; b < n; ++b) {
    RequireNonNegative(Indexed("inv_mass", b), p.inv_mass[b]);
    if (b < p.inv_inertia.size()) RequireNonNegative(Indexed("inv_inertia", b), p.inv_inertia[b]);
    RequireFinite(Indexed("free_velocity", b) + ".x", p.free_velocity[b].x());
    RequireFinite(Indexed("free_velocity", b) + ".y", p.free_velocity[b].y());
    if (b < p.free_spin.size()) RequireFinite(Indexed("free_spin", b), p.free_spin[b]);
  }
}

void ValidateContact(const ContactProblem& p, std::size_t k) {
  const ProblemContact& c = p.contacts[k];
  const std::string name = Indexed("contacts", k);
  for (const int body : {c.body_i, c.body_j}) {
    if (body < -1 || body >= p.NumBodies()) {
      RejectProblem(name + " names body " + std::to_string(body) + ", outside [-1, " +
                    std::to_string(p.NumBodies()) + ")");
    }
  }
  if (!(std::abs(c.normal.norm() - 1.0) <= 1e-6)) {
    RejectProblem(name + ".normal has length " + std::to_string(c.normal.norm()) + ", not 1");
  }
  RequireNonNegative(name + ".mu", c.mu);
  for (const double value :
       {c.arm_i, c.arm_j, c.cell_arm, c.target_velocity, c.bias.x(), c.bias.y()}) {
    RequireFinite(name + " (arm, cell arm, target velocity or bias)", value);
  }
}

}  // namespace

void Validate(const ContactProblem& p) {
  if (!(p.dt > 0.0) || !std::isfinite(p.dt)) {
    RejectProblem("dt is " + std::to_string(p.dt) + " (must be finite and > 0)");
  }
  ValidateBodies(p);
  if (p.cell) {
    RequireNonNegative("cell.inv_mass", p.cell->inv_mass);
    RequireFinite("cell.free_rate", p.cell->free_rate);
  }
  for (std::size_t k = 0; k < p.contacts.size(); ++k) ValidateContact(p, k);
}

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// Adds the Jacobian entries of one side (sign −1 for i, +1 for j) of contact k.
void AddSide(const ContactProblem& p, int row, int body, double sign, double arm, const Vec2& n,
             Triplets& t) {
  if (body < 0) return;
  const int col = body * p.DofsPerBody();
  t.emplace_back(row, col, sign * n.x());
  t.emplace_back(row, col + 1, sign * n.y());
  if (!p.frictional) return;
  const Vec2 tangent = Perp(n);
  t.emplace_back(row + 1, col, sign * tangent.x());
  t.emplace_back(row + 1, col + 1, sign * tangent.y());
  t.emplace_back(row + 1, col + 2, -arm);
}

}  // namespace

Eigen::SparseMatrix<double> AssembleJacobian(const ContactProblem& p) {
  Triplets t;
  t.reserve(p.NumContacts() * (p.frictional ? 11 : 5));
  const int stride = p.UnknownsPerContact();
  for (int k = 0; k < p.NumContacts(); ++k) {
    const ProblemContact& c = p.contacts[k];
    AddSide(p, k * stride, c.body_i, -1.0, c.arm_i, c.normal, t);
    AddSide(p, k * stride, c.body_j, +1.0, c.arm_j, c.normal, t);
    if (p.cell && c.cell_arm != 0.0) t.emplace_back(k * stride, p.NumDofs() - 1, c.cell_arm);
  }
  Eigen::SparseMatrix<double> h(p.NumUnknowns(), p.NumDofs());
  h.setFromTriplets(t.begin(), t.end());
  return h;
}

Eigen::VectorXd InverseMassDiagonal(const ContactProblem& p) {
  Eigen::VectorXd m(p.NumDofs());
  const int d = p.DofsPerBody();
  for (int b = 0; b < p.NumBodies(); ++b) {
    m[d * b] = m[d * b + 1] = p.inv_mass[b];
    if (p.frictional) m[d * b + 2] = p.inv_inertia[b];
  }
  if (p.cell) m[p.NumDofs() - 1] = p.cell->inv_mass;
  return m;
}

Eigen::VectorXd FreeVelocityVector(const ContactProblem& p) {
  Eigen::VectorXd v(p.NumDofs());
  const int d = p.DofsPerBody();
  for (int b = 0; b < p.NumBodies(); ++b) {
    v[d * b] = p.free_velocity[b].x();
    v[d * b + 1] = p.free_velocity[b].y();
    if (p.frictional) v[d * b + 2] = p.free_spin[b];
  }
  if (p.cell) v[p.NumDofs() - 1] = p.cell->free_rate;
  return v;
}

Eigen::VectorXd VelocityOffset(const ContactProblem& p) {
  Eigen::VectorXd offset(p.NumUnknowns());
  const int stride = p.UnknownsPerContact();
  for (int k = 0; k < p.NumContacts(); ++k) {
    const ProblemContact& c = p.contacts[k];
    offset[k * stride] = c.bias.x() - c.target_velocity;
    if (p.frictional) offset[k * stride + 1] = c.bias.y();
  }
  return offset;
}

Eigen::SparseMatrix<double> AssembleDelassus(const ContactProblem& p) {
  const Eigen::SparseMatrix<double> h = AssembleJacobian(p);
  const Eigen::SparseMatrix<double> w = h * InverseMassDiagonal(p).asDiagonal() * h.transpose();
  return w;
}

Eigen::VectorXd DelassusOffset(const ContactProblem& p) {
  return AssembleJacobian(p) * FreeVelocityVector(p) + VelocityOffset(p);
}

Eigen::VectorXd EndVelocity(const ContactProblem& p, const Eigen::VectorXd& impulses) {
  const Eigen::SparseMatrix<double> h = AssembleJacobian(p);
  Eigen::VectorXd generalized = h.transpose() * impulses;
  return FreeVelocityVector(p) + InverseMassDiagonal(p).cwiseProduct(generalized);
}

Eigen::VectorXd PosedContactVelocity(const ContactProblem& p, const Eigen::VectorXd& impulses) {
  return AssembleJacobian(p) * EndVelocity(p, impulses) + VelocityOffset(p);
}

}  // namespace unjam
