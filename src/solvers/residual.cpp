// The backend-independent residual: natural map of Signorini–Coulomb with the De Saxcé
// shift, per contact, in impulse units, normalised by an impulse scale. See residual.hpp.
// Both problem forms reduce to the same per-contact error and the same normalisation.
#include "unjam/solvers/residual.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

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

// ρ from the local Delassus diagonal (W_nn, W_tt): 1/W_nn, else 1/W_tt, else 0.
double WeightFromDiagonal(const Eigen::Vector2d& w) {
  if (w[0] > 0.0) return 1.0 / w[0];
  return w[1] > 0.0 ? 1.0 / w[1] : 0.0;
}

// e_k of one contact with posed velocity u = (ũ_n, u_t) and weight ρ.
double ContactError(const ContactLaw& law, bool frictional, double rho, const Eigen::Vector2d& r,
                    const Eigen::Vector2d& u) {
  if (law.kind == ConstraintKind::kBilateral) {
    return std::hypot(rho * u[0], frictional ? r[1] : 0.0);
  }
  if (!frictional) {
    return std::abs(r[0] - std::max(0.0, r[0] - rho * u[0]));
  }
  // One scalar ρ for both components: a diagonal scaling would tilt the normal cone of a
  // sliding contact and make the exact solution look wrong.
  const Eigen::Vector2d shifted(u[0] + law.mu * std::abs(u[1]), u[1]);
  return (r - ProjectOnCone(r - rho * shifted, law.mu)).norm();
}

// The residual from its per-contact inputs, whichever form they come from: the errors e_k,
// Σ|r_n|, and the largest ρ|ũ_n| of the free motion (no impulses).
ResidualBreakdown Summary(const std::vector<double>& errors, double sum_rn, double free_scale) {
  ResidualBreakdown out;
  const int nc = static_cast<int>(errors.size());
  if (nc == 0) return out;
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

ContactLaw LawOf(const ProblemContact& c) { return {c.mu, c.kind}; }

Eigen::Vector2d Pair(const Eigen::VectorXd& x, int k) {
  return Eigen::Vector2d(x[2 * k], x[2 * k + 1]);
}

}  // namespace

double ResidualWeight(const ContactProblem& p, int k) {
  return WeightFromDiagonal(DelassusDiagonal(p, k));
}

double ResidualWeight(const DelassusProblem& p, int k) {
  return WeightFromDiagonal(
      Eigen::Vector2d(p.w.coeff(2 * k, 2 * k), p.w.coeff(2 * k + 1, 2 * k + 1)));
}

ResidualEvaluator::ResidualEvaluator(const ContactProblem& p) : p_(p) {
  const VelocityState v_free = FreeVelocityState(p);
  rho_.resize(p.NumContacts());
  for (int k = 0; k < p.NumContacts(); ++k) {
    rho_[k] = ResidualWeight(p, k);
    free_scale_ = std::max(free_scale_, rho_[k] * std::abs(PosedVelocity(p, v_free, k)[0]));
  }
}

VelocityState ResidualEvaluator::Velocities(const Eigen::VectorXd& impulses) const {
  return EndVelocityState(p_, impulses);
}

void ResidualEvaluator::Errors(const Eigen::VectorXd& impulses, const VelocityState& v, int begin,
                               int end, std::vector<double>& errors) const {
  const int stride = p_.UnknownsPerContact();
  for (int k = begin; k < end; ++k) {
    const Eigen::Vector2d r(impulses[k * stride], p_.frictional ? impulses[k * stride + 1] : 0.0);
    errors[k] =
        ContactError(LawOf(p_.contacts[k]), p_.frictional, rho_[k], r, PosedVelocity(p_, v, k));
  }
}

ResidualBreakdown ResidualEvaluator::Summarise(const Eigen::VectorXd& impulses,
                                               const std::vector<double>& errors) const {
  double sum_rn = 0.0;
  const int stride = p_.UnknownsPerContact();
  for (int k = 0; k < p_.NumContacts(); ++k) sum_rn += std::abs(impulses[k * stride]);
  return Summary(errors, sum_rn, free_scale_);
}

ResidualBreakdown ResidualEvaluator::operator()(const Eigen::VectorXd& impulses) const {
  std::vector<double> errors(p_.NumContacts());
  Errors(impulses, Velocities(impulses), 0, p_.NumContacts(), errors);
  return Summarise(impulses, errors);
}

ResidualBreakdown ComputeResidual(const ContactProblem& p, const Eigen::VectorXd& impulses) {
  return ResidualEvaluator(p)(impulses);
}

ResidualBreakdown ComputeResidual(const DelassusProblem& p, const Eigen::VectorXd& impulses) {
  const int nc = p.NumContacts();
  const Eigen::VectorXd u = p.w * impulses + p.q;
  const Eigen::VectorXd diagonal = p.w.diagonal();
  std::vector<double> errors(nc);
  double sum_rn = 0.0, free_scale = 0.0;
  for (int k = 0; k < nc; ++k) {
    const Eigen::Vector2d r = Pair(impulses, k);
    const double rho = WeightFromDiagonal(Pair(diagonal, k));
    errors[k] = ContactError(p.laws[k], true, rho, r, Pair(u, k));
    sum_rn += std::abs(r[0]);
    free_scale = std::max(free_scale, rho * std::abs(p.q[2 * k]));
  }
  return Summary(errors, sum_rn, free_scale);
}

double SiconosError(const DelassusProblem& p, const Eigen::VectorXd& impulses) {
  const Eigen::VectorXd u = p.w * impulses + p.q;
  double sum_sq = 0.0;
  for (int k = 0; k < p.NumContacts(); ++k) {
    const double e = ContactError(p.laws[k], true, 1.0, Pair(impulses, k), Pair(u, k));
    sum_sq += e * e;
  }
  const double norm = std::max({impulses.norm(), u.norm(), p.q.norm()});
  const double error = std::sqrt(sum_sq);
  return norm > DBL_EPSILON ? error / norm : error;
}

}  // namespace unjam
