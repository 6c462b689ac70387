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
//
// The Delassus form (delassus_problem.hpp) is judged by the same formula, with ũ = W r + q
// and ρ_k from the diagonal of W, so that a packing's problem and its export give the same
// residual for the same impulses (to rounding: W is assembled, not recomputed per body).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "unjam/problem/contact_problem.hpp"
#include "unjam/problem/delassus_problem.hpp"
#include "unjam/problem/kinematics.hpp"

namespace unjam {

struct ResidualBreakdown {
  double residual = 0.0;  // max_k e_k / scale
  double rms = 0.0;       // sqrt(mean e_k²) / scale
  double scale = 0.0;     // the impulse scale used
  int worst_contact = -1;
};

// ρ_k of the natural map: 1/W_nn (1/W_tt if W_nn vanishes, 0 if both do). Backends that
// pose the law with an augmentation parameter use the same one (newton.cpp).
double ResidualWeight(const ContactProblem& problem, int k);
double ResidualWeight(const DelassusProblem& problem, int k);

ResidualBreakdown ComputeResidual(const ContactProblem& problem, const Eigen::VectorXd& impulses);
ResidualBreakdown ComputeResidual(const DelassusProblem& problem, const Eigen::VectorXd& impulses);

// The residual of many impulse vectors of one body problem (an iterative solver's checks):
// the weights ρ and the free motion's scale are computed once, and the per-contact errors
// may be split among threads (`Errors`, then `Summarise`). Bit for bit ComputeResidual.
class ResidualEvaluator {
 public:
  explicit ResidualEvaluator(const ContactProblem& problem);  // keeps a reference
  ResidualBreakdown operator()(const Eigen::VectorXd& impulses) const;
  // The end velocities of `impulses`, the errors of contacts [begin, end) into `errors`
  // (sized NumContacts()), and the summary of all of them.
  VelocityState Velocities(const Eigen::VectorXd& impulses) const;
  void Errors(const Eigen::VectorXd& impulses, const VelocityState& v, int begin, int end,
              std::vector<double>& errors) const;
  ResidualBreakdown Summarise(const Eigen::VectorXd& impulses,
                              const std::vector<double>& errors) const;

 private:
  const ContactProblem& p_;
  std::vector<double> rho_;
  double free_scale_ = 0.0;
};

// Siconos' 2D error (fc2d_compute_error, /work/shared/FORMATS.md): the l2 norm over all
// contacts of the same natural map with ρ = 1, r − Π_K(r − (u + μ|u_t| e_n)), divided by
// max(‖r‖, ‖u‖, ‖q‖) with u = W r + q (not divided if that is below machine epsilon). A held
// contact, which Siconos cannot pose, contributes ‖(u_n, r_t)‖. Offered beside the unjam
// residual for side-by-side numbers; it is not what tolerances apply to.
double SiconosError(const DelassusProblem& problem, const Eigen::VectorXd& impulses);

// Projection of the impulse (r_n, r_t) on the 2D Coulomb cone |r_t| ≤ μ r_n.
Eigen::Vector2d ProjectOnCone(const Eigen::Vector2d& r, double mu);

}  // namespace unjam
