// The backend-independent residual (docs/residual.md).
//
// Per contact k, with posed velocity ũ_k (normal shifted by the gap target) and the
// De Saxcé shift ŭ_k = (ũ_n + μ|u_t|, u_t), the natural map
//     e_k = ‖ r_k − Π_K(r_k − ρ_k ŭ_k) ‖
// with K the Coulomb cone (or the half-line r_n ≥ 0 without friction, or the bilateral
// set {r_t = 0}), and ρ_k = 1 / W_kk (local effective mass, so that ρ ũ is an impulse).
// e_k = 0 exactly when contact k obeys Signorini–Coulomb. The reported residual is
//     max_k e_k / s,   s = mean |r_n| over contacts (a force scale, in impulse units),
// falling back to the load scale of the problem when every impulse vanishes.
#pragma once

#include <Eigen/Core>

#include "unjam/problem/contact_problem.hpp"

namespace unjam {

struct ResidualBreakdown {
  double residual = 0.0;       // max_k e_k / scale
  double rms = 0.0;            // sqrt(mean e_k²) / scale
  double scale = 0.0;          // the impulse scale used
  int worst_contact = -1;
};

// ρ_k of the natural map: 1/W_nn (1/W_tt if W_nn vanishes, 0 if both do). Backends that
// pose the law with an augmentation parameter use the same one (newton.cpp).
double ResidualWeight(const ContactProblem& problem, int k);

ResidualBreakdown ComputeResidual(const ContactProblem& problem, const Eigen::VectorXd& impulses);

// Projection of the impulse (r_n, r_t) on the 2D Coulomb cone |r_t| ≤ μ r_n.
Eigen::Vector2d ProjectOnCone(const Eigen::Vector2d& r, double mu);

}  // namespace unjam
