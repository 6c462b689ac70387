// Loop (matrix-free) versions of r ↦ v ↦ ũ for a ContactProblem. Same mathematics as the
// sparse views in contact_problem.hpp (tested against them), without assembling matrices:
// these run inside solver loops.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "unjam/problem/contact_problem.hpp"

namespace unjam {

// Generalised velocity state: per body (vx, vy, ω) (ω unused without friction), and λ.
struct VelocityState {
  std::vector<Eigen::Vector3d> body;
  double cell_rate = 0.0;
};

VelocityState FreeVelocityState(const ContactProblem& problem);
// v = v_free + M⁻¹ Hᵀ r.
VelocityState EndVelocityState(const ContactProblem& problem, const Eigen::VectorXd& impulses);
// Posed velocity ũ_k = (u_n − target, u_t) of contact k.
Eigen::Vector2d PosedVelocity(const ContactProblem& problem, const VelocityState& v, int k);
// The diagonal Delassus block of contact k, (W_nn, W_tt): for disks the normal impulse
// exerts no torque, so the block is diagonal. A side without degrees of freedom adds
// nothing; the cell adds c_k² / (M_λ D V) to W_nn. W_tt is 0 without friction.
Eigen::Vector2d DelassusDiagonal(const ContactProblem& problem, int k);
// Adds M⁻¹ Hᵀ of the impulse (dn, dt) of contact k to v.
void ApplyImpulse(const ContactProblem& problem, int k, double dn, double dt, VelocityState& v);

}  // namespace unjam
