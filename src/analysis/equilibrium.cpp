#include "unjam/analysis/equilibrium.hpp"

#include <algorithm>
#include <cmath>

namespace unjam {

EquilibriumReport CheckEquilibrium(const Scene& scene, const std::vector<Contact>& contacts,
                                   const std::vector<Eigen::Vector2d>& forces) {
  EquilibriumReport out;
  const int n = static_cast<int>(scene.particles.size());
  std::vector<Vec2> net(n, Vec2::Zero());
  std::vector<double> torque(n, 0.0);
  double sum_fn = 0.0;
  double virial = 0.0;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    const Vec2 f = forces[k][0] * c.normal + forces[k][1] * Perp(c.normal);
    if (forces[k][0] > 0.0) {
      sum_fn += forces[k][0];
      ++out.force_carrying_contacts;
    }
    net[c.i] -= f;
    torque[c.i] += Cross(c.branch_i, -f);
    if (!c.WithWall()) {
      net[c.j] += f;
      torque[c.j] += Cross(c.branch_j, f);
      virial += f.dot(c.center_to_center);
    }
  }
  out.mean_contact_force =
      out.force_carrying_contacts > 0 ? sum_fn / out.force_carrying_contacts : 0.0;
  const std::vector<char> movable = MovableParticles(scene);
  double mean_radius = 0.0;
  for (const Particle& p : scene.particles) mean_radius += p.radius / n;
  const double scale = out.mean_contact_force > 0.0 ? out.mean_contact_force : 1.0;
  for (int i = 0; i < n; ++i) {
    if (!movable[i]) continue;
    Vec2 total = net[i];
    if (scene.effects.gravity) total += scene.particles[i].Mass() * *scene.effects.gravity;
    const double fi = total.norm() / scale;
    const double ti = std::abs(torque[i]) / (scale * mean_radius);
    if (std::max(fi, ti) > out.residual) {
      out.residual = std::max(fi, ti);
      out.worst_particle = i;
    }
    out.max_force_imbalance = std::max(out.max_force_imbalance, fi);
    out.max_torque_imbalance = std::max(out.max_torque_imbalance, ti);
  }
  if (PeriodicY(scene.cell.periodicity)) {
    out.pressure = virial / (kDimension * scene.cell.size.x() * scene.cell.size.y());
  }
  return out;
}

namespace {
// z and rattlers from the number of force-carrying contacts of each particle.
Coordination FromCounts(const Scene& scene, const std::vector<int>& count, int carrying_contacts) {
  Coordination out;
  out.force_carrying_contacts = carrying_contacts;
  const int n = static_cast<int>(scene.particles.size());
  long ends = 0;
  int carrying = 0;
  for (int i = 0; i < n; ++i) {
    if (scene.particles[i].fixed) continue;
    if (count[i] == 0) {
      ++out.rattlers;
    } else {
      ++carrying;
      ends += count[i];
    }
  }
  out.z = carrying > 0 ? static_cast<double>(ends) / carrying : 0.0;
  const int free = carrying + out.rattlers;
  out.z_with_rattlers = free > 0 ? static_cast<double>(ends) / free : 0.0;
  return out;
}
}  // namespace

Coordination ComputeCoordination(const Scene& scene, const std::vector<Contact>& contacts,
                                 const std::vector<Eigen::Vector2d>& forces) {
  std::vector<double> normals;
  for (const Eigen::Vector2d& f : forces) normals.push_back(f[0]);
  const double threshold = CarryingThreshold(normals);
  std::vector<int> count(scene.particles.size(), 0);
  int carrying = 0;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (!(forces[k][0] > threshold)) continue;
    ++carrying;
    ++count[contacts[k].i];
    if (!contacts[k].WithWall()) ++count[contacts[k].j];
  }
  return FromCounts(scene, count, carrying);
}

Coordination ComputeCoordination(const Scene& scene, const std::vector<ContactForce>& forces) {
  const double threshold = CarryingThreshold(forces);
  std::vector<int> count(scene.particles.size(), 0);
  int carrying = 0;
  for (const ContactForce& f : forces) {
    if (!(f.normal > threshold)) continue;
    ++carrying;
    ++count[f.i];
    if (!IsWallIndex(f.j)) ++count[f.j];
  }
  return FromCounts(scene, count, carrying);
}

}  // namespace unjam
