// The linear equilibrium system of a static packing: A f = b.
//
// Unknowns: the contact forces f = (f_n, f_t) of every closed contact (|gap| ≤ the closed
// tolerance; f_t only with friction), acting on j as f_n n + f_t t and on i with the
// opposite sign (contact.hpp). Rows: the force balance of every free particle (x, y and,
// with friction, the torque −R f_t of each contact), and under a pressure bath the balance
// of the cell: the virial Σ_k f_n,k (l_k·n_k) equals D V P_ext (that row is multiplied by
// F/(D V P_ext), F = 2 R̄ P_ext, so that it reads in force units and its residual over F is
// the relative pressure mismatch). Fixed particles and particles with prescribed motion do
// not have to balance. The load b is −m_i g on the force rows (gravity), 0 on torques, F on
// the cell row.
//
// A set of forces is admissible (a static state) when A f = b, f_n ≥ 0 and |f_t| ≤ μ f_n
// (in 2D the Coulomb cone is two half-planes): the force ensemble of docs/indeterminacy.md.
// A particle without closed contacts has an empty row: under gravity the system is then
// infeasible (the particle would fall), without load the row is dropped.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "unjam/contacts/contact.hpp"
#include "unjam/scene/scene.hpp"

namespace unjam {

struct EquilibriumSystemOptions {
  double closed_gap_tolerance = 1e-9;  // length units, as the static solve
  double margin = 1e-6;                // contacts are detected up to this gap
};

struct EquilibriumSystem {
  std::vector<Contact> contacts;     // the closed contacts, the unknowns' order
  std::vector<Vec2> contact_points;  // per contact: x_i + branch_i (as seen from i)
  bool frictional = false;           // two unknowns per contact, else one
  double mu = 0.0;
  Eigen::SparseMatrix<double> matrix;  // A: rows × UnknownsPerContact()·contacts
  Eigen::VectorXd load;                // b
  std::vector<int> row_particle;       // particle of each row, −1 for the cell row
  double force_scale = 1.0;            // typical force: mean |b| of the force rows, or P_ext·2R̄
  // Deepest overlap among the contacts (≥ 0); a static state has none beyond the tolerance.
  double max_overlap = 0.0;

  int UnknownsPerContact() const { return frictional ? 2 : 1; }
  int NumUnknowns() const { return static_cast<int>(contacts.size()) * UnknownsPerContact(); }
  int NumRows() const { return static_cast<int>(load.size()); }
};

EquilibriumSystem BuildEquilibriumSystem(const Scene& scene,
                                         const EquilibriumSystemOptions& options = {});

// Forces (f_n, f_t) per contact of the system from the forces stored with a scene (matched by
// particles and image; zero where none is stored), as one vector of unknowns.
Eigen::VectorXd StoredForcesOf(const EquilibriumSystem& system,
                               const std::vector<ContactForce>& stored);

// The scene's force list (force-carrying contacts only) from a vector of unknowns.
std::vector<ContactForce> ToContactForces(const EquilibriumSystem& system,
                                          const Eigen::VectorXd& forces);

}  // namespace unjam
