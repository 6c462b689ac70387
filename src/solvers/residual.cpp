// The backend-independent residual: natural map of Signorini–Coulomb with the De Saxcé
// shift, per contact, in impulse units, normalised by an impulse scale. See residual.hpp.
#include "unjam/solvers/residual.hpp"

#include <algorithm>
#include <cmath>

#include "unjam/problem/kinematics.hpp"

namespace unjam {

Eigen::Vector2d ProjectOnCone(const Eigen::Vector2d& r, double mu) {
  const double rn = r[0];
  const double rt = r[1];
  // The polar cone first: with μ = 0 a point (r_n < 0, 0) would otherwise pass the
  // "inside" test |r_t| ≤ μ r_n (0 ≤ −0).
  if (mu * std::abs(rt) <= -rn) return Eigen::Vector2d::Zero();  // inside the polar cone
  if (std::abs(rt) <= mu * rn) return r;                         // inside the cone
  // Onto the nearer edge (1, ±μ)/√(1+μ²).
  const double s = rt >= 0.0 ? 1.0 : -1.0;
  const double along = (rn + mu * s * rt) / (1.0 + mu * mu);
  return Eigen::Vector2d(along, mu * s * along);
}

namespace {

// Local effective masses 1/W_nn and 1/W_tt of contact k (0 where W vanishes).
Eigen::Vector2d LocalMass(const ContactProblem& p, int k) {
  const Eigen::Vector2d w = DelassusDiagonal(p, k);
  return Eigen::Vector2d(w[0] > 0.0 ? 1.0 / w[0] : 0.0, w[1] > 0.0 ? 1.0 / w[1] : 0.0);
}

double ContactError(const ContactProblem& p, int k, const Eigen::Vector2d& r,
                    const Eigen::Vector2d& u) {
  const ProblemContact& c = p.contacts[k];
  const double rho = ResidualWeight(p, k);
  if (c.kind == ConstraintKind::kBilateral) {
    return std::hypot(rho * u[0], p.frictional ? r[1] : 0.0);
  }
  if (!p.frictional) {
    return std::abs(r[0] - std::max(0.0, r[0] - rho * u[0]));
  }
  // One scalar ρ for both components: a diagonal scaling would tilt the normal cone of a
  // sliding contact and make the exact solution look wrong.
  const Eigen::Vector2d shifted(u[0] + c.mu * std::abs(u[1]), u[1]);
  return (r - ProjectOnCone(r - rho * shifted, c.mu)).norm();
}

}  // namespace

double ResidualWeight(const ContactProblem& p, int k) {
  const Eigen::Vector2d m = LocalMass(p, k);
  return m[0] > 0.0 ? m[0] : m[1];
}

ResidualBreakdown ComputeResidual(const ContactProblem& p, const Eigen::VectorXd& impulses) {
  ResidualBreakdown out;
  const int nc = p.NumContacts();
  if (nc == 0) return out;
  const int stride = p.UnknownsPerContact();
  const VelocityState v = EndVelocityState(p, impulses);
  std::vector<double> errors(nc);
  double sum_rn = 0.0;
  double free_scale = 0.0;
  const VelocityState v_free = FreeVelocityState(p);
  for (int k = 0; k < nc; ++k) {
    const Eigen::Vector2d r(impulses[k * stride], p.frictional ? impulses[k * stride + 1] : 0.0);
    errors[k] = ContactError(p, k, r, PosedVelocity(p, v, k));
    sum_rn += std::abs(r[0]);
    free_scale = std::max(free_scale, ResidualWeight(p, k) * std::abs(PosedVelocity(p, v_free, k)[0]));
  }
  // Impulse scale: the mean normal impulse; without any impulse, the largest one a single
  // contact would need to stop its free approach; failing that, 1.
  out.scale = sum_rn > 0.0 ? sum_rn / nc : (free_scale > 0.0 ? free_scale : 1.0);
  double sum_sq = 0.0;
  for (int k = 0; k < nc; ++k) {
    sum_sq += errors[k] * errors[k];
    if (out.worst_contact < 0 || errors[k] > errors[out.worst_contact]) out.worst_contact = k;
  }
  out.residual = errors[out.worst_contact] / out.scale;
  out.rms = std::sqrt(sum_sq / nc) / out.scale;
  return out;
}

}  // namespace unjam
