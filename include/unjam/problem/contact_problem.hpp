// The contact problem of one time step: plain data that every backend reads unchanged.
//
// Degrees of freedom. Each free particle is a body with translational velocity v_b and,
// in a frictional problem, a spin ω_b. Fixed particles, walls and particles with
// prescribed motion have no degrees of freedom: their velocity enters a contact through
// the constant `bias`. A pressure-bath scene adds one global degree of freedom, the cell
// strain rate λ.
//
// Contact kinematics (n from i to j, t = Perp(n), arms a_i = R_i, a_j = R_j):
//   u_n = n·(v_j − v_i) + c_k λ + bias_n          c_k = l_k·n (centre-to-centre vector l_k)
//   u_t = t·(v_j − v_i) − a_i ω_i − a_j ω_j + bias_t
// i.e. u = H v + bias with H the sparse contact Jacobian. The impulse r_k = (r_n, r_t)
// acts on j as r_n n + r_t t and on i with the opposite sign; the generalised impulse is
// Hᵀ r. End-of-step velocities are v = v_free + M⁻¹ Hᵀ r.
//
// Contact laws (per contact k, with the position-level Signorini condition):
//   unilateral:  ũ_n = u_n + g_k/Δt ≥ 0,  r_n ≥ 0,  ũ_n r_n = 0          (Signorini)
//                |r_t| ≤ μ r_n; |r_t| < μ r_n ⇒ u_t = 0; else r_t = −μ r_n sign(u_t)
//   bilateral:   u_n + (g_k − g_target)/Δt = 0, r_n free, r_t = 0       (held contact)
// g_k is the gap at the start of the step; a negative gap (overlap) is corrected by the
// fraction `overlap_correction` of the step (1 = removed within the step).
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "unjam/scene/scene.hpp"

namespace unjam {

enum class ConstraintKind { kUnilateral, kBilateral };

struct ProblemContact {
  int body_i = -1;  // body index, or −1: no degrees of freedom
  int body_j = -1;
  Vec2 normal = Vec2(1.0, 0.0);
  double arm_i = 0.0;  // lever arm of the tangential impulse on i (R_i), rotation only
  double arm_j = 0.0;
  double cell_arm = 0.0;         // c_k = l_k·n, coupling to the cell strain rate λ
  double target_velocity = 0.0;  // the law is posed on ũ_n = u_n − target_velocity
  Vec2 bias = Vec2::Zero();      // (normal, tangential) relative velocity from sides without dofs
  double mu = 0.0;
  ConstraintKind kind = ConstraintKind::kUnilateral;
  // Height of the contact point against gravity (−ĝ·x), 0 in a scene without gravity.
  // Not part of the law: only the sweep order SweepOrder::kHeight reads it.
  double height = 0.0;
};

// The cell strain rate λ as a degree of freedom: λ = free_rate + inv_mass Σ_k c_k r_n,k.
struct CellDof {
  double inv_mass = 0.0;   // 1 / (M_λ D V)
  double free_rate = 0.0;  // λ after the external pressure and kinetic terms, before contacts
};

struct ContactProblem {
  double dt = 0.0;
  bool frictional = false;          // two unknowns per contact and rotations; else one unknown
  std::vector<double> inv_mass;     // per body
  std::vector<double> inv_inertia;  // per body (frictional problems only)
  std::vector<Vec2> free_velocity;  // per body
  std::vector<double> free_spin;    // per body (frictional problems only)
  std::optional<CellDof> cell;
  std::vector<ProblemContact> contacts;
  // What a solve starts from is not part of the problem: SolverGuess (contact_solver.hpp).

  int NumBodies() const { return static_cast<int>(inv_mass.size()); }
  int NumContacts() const { return static_cast<int>(contacts.size()); }
  int UnknownsPerContact() const { return frictional ? 2 : 1; }
  int NumUnknowns() const { return NumContacts() * UnknownsPerContact(); }
  int DofsPerBody() const { return frictional ? 3 : 2; }
  // Generalised velocity layout: body b at [DofsPerBody()·b, …), then λ if present.
  int NumDofs() const { return NumBodies() * DofsPerBody() + (cell ? 1 : 0); }
};

// Sparse views of the same data, for backends that want matrices.
// H: NumUnknowns() × NumDofs(); rows per contact (n[, t]).
// Throws std::invalid_argument naming the field, the index and the rule where the problem
// is inconsistent: per-body arrays of another size than inv_mass (inv_inertia and free_spin
// may be empty without friction), a contact's body outside [−1, NumBodies()), a normal not
// of unit length (1e-6), a negative or non-finite inverse mass, friction coefficient or
// time step, or a non-finite velocity, bias or target.
void Validate(const ContactProblem& problem);

Eigen::SparseMatrix<double> AssembleJacobian(const ContactProblem& problem);
Eigen::VectorXd InverseMassDiagonal(const ContactProblem& problem);  // size NumDofs()
Eigen::VectorXd FreeVelocityVector(const ContactProblem& problem);   // size NumDofs()
// Offset so that the posed velocity is ũ = H v + offset (bias and −target_velocity).
Eigen::VectorXd VelocityOffset(const ContactProblem& problem);
// Delassus operator W = H M⁻¹ Hᵀ and q, so that ũ = W r + q (the Siconos form).
Eigen::SparseMatrix<double> AssembleDelassus(const ContactProblem& problem);
Eigen::VectorXd DelassusOffset(const ContactProblem& problem);

// End-of-step generalised velocity v = v_free + M⁻¹ Hᵀ r.
Eigen::VectorXd EndVelocity(const ContactProblem& problem, const Eigen::VectorXd& impulses);
// Posed contact velocities ũ (normal entry shifted by the target), size NumUnknowns().
Eigen::VectorXd PosedContactVelocity(const ContactProblem& problem,
                                     const Eigen::VectorXd& impulses);

}  // namespace unjam
