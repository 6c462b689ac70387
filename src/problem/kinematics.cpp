#include "unjam/problem/kinematics.hpp"

#include <utility>

namespace unjam {

VelocityState FreeVelocityState(const ContactProblem& p) {
  VelocityState v;
  v.body.resize(p.NumBodies());
  for (int b = 0; b < p.NumBodies(); ++b) {
    v.body[b] = Eigen::Vector3d(p.free_velocity[b].x(), p.free_velocity[b].y(),
                                p.frictional ? p.free_spin[b] : 0.0);
  }
  if (p.cell) v.cell_rate = p.cell->free_rate;
  return v;
}

Eigen::Vector2d DelassusDiagonal(const ContactProblem& p, int k) {
  const ProblemContact& c = p.contacts[k];
  double wn = 0.0;
  double wt = 0.0;
  for (auto [body, arm] : {std::pair{c.body_i, c.arm_i}, std::pair{c.body_j, c.arm_j}}) {
    if (body < 0) continue;
    wn += p.inv_mass[body];
    if (p.frictional) wt += p.inv_mass[body] + arm * arm * p.inv_inertia[body];
  }
  if (p.cell) wn += c.cell_arm * c.cell_arm * p.cell->inv_mass;
  return Eigen::Vector2d(wn, wt);
}

void ApplyImpulse(const ContactProblem& p, int k, double dn, double dt, VelocityState& v) {
  const ProblemContact& c = p.contacts[k];
  const Vec2 impulse = dn * c.normal + dt * Perp(c.normal);
  if (c.body_i >= 0) {
    Eigen::Vector3d& vi = v.body[c.body_i];
    vi.head<2>() -= p.inv_mass[c.body_i] * impulse;
    if (p.frictional) vi[2] -= p.inv_inertia[c.body_i] * c.arm_i * dt;
  }
  if (c.body_j >= 0) {
    Eigen::Vector3d& vj = v.body[c.body_j];
    vj.head<2>() += p.inv_mass[c.body_j] * impulse;
    if (p.frictional) vj[2] -= p.inv_inertia[c.body_j] * c.arm_j * dt;
  }
  if (p.cell) v.cell_rate += p.cell->inv_mass * c.cell_arm * dn;
}

VelocityState EndVelocityState(const ContactProblem& p, const Eigen::VectorXd& impulses) {
  VelocityState v = FreeVelocityState(p);
  const int stride = p.UnknownsPerContact();
  for (int k = 0; k < p.NumContacts(); ++k) {
    ApplyImpulse(p, k, impulses[k * stride], p.frictional ? impulses[k * stride + 1] : 0.0, v);
  }
  return v;
}

Eigen::Vector2d PosedVelocity(const ContactProblem& p, const VelocityState& v, int k) {
  const ProblemContact& c = p.contacts[k];
  Vec2 relative = Vec2::Zero();
  double spin_term = 0.0;
  if (c.body_i >= 0) {
    relative -= v.body[c.body_i].head<2>();
    spin_term -= c.arm_i * v.body[c.body_i][2];
  }
  if (c.body_j >= 0) {
    relative += v.body[c.body_j].head<2>();
    spin_term -= c.arm_j * v.body[c.body_j][2];
  }
  double un = c.normal.dot(relative) + c.bias.x() - c.target_velocity;
  if (p.cell) un += c.cell_arm * v.cell_rate;
  const double ut = p.frictional ? Perp(c.normal).dot(relative) + spin_term + c.bias.y() : 0.0;
  return Eigen::Vector2d(un, ut);
}

}  // namespace unjam
