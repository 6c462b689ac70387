#include "unjam/indeterminacy/equilibrium_system.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace unjam {

namespace {

// Rows of particle i: force x, force y and (with friction) torque; −1 if it need not balance.
std::vector<int> NumberRows(const Scene& scene, const std::vector<char>& free,
                            const std::vector<int>& contact_count, int per_particle,
                            std::vector<int>& row_particle) {
  std::vector<int> first_row(scene.particles.size(), -1);
  const bool loaded = scene.effects.gravity.has_value();
  for (std::size_t i = 0; i < scene.particles.size(); ++i) {
    // Without a load, a particle without contacts (a rattler) balances trivially.
    if (!free[i] || (contact_count[i] == 0 && !loaded)) continue;
    first_row[i] = static_cast<int>(row_particle.size());
    for (int a = 0; a < per_particle; ++a) row_particle.push_back(static_cast<int>(i));
  }
  return first_row;
}

}  // namespace

EquilibriumSystem BuildEquilibriumSystem(const Scene& scene, const EquilibriumSystemOptions& o) {
  EquilibriumSystem out;
  out.frictional = scene.effects.Frictional();
  out.mu = scene.effects.friction;
  const std::vector<char> free = MovableParticles(scene);
  std::vector<int> contact_count(scene.particles.size(), 0);
  for (Contact& c : DetectContacts(scene, o.margin)) {
    const bool moves = free[c.i] || (!c.WithWall() && free[c.j]);
    if (c.gap > o.closed_gap_tolerance || !moves) continue;
    out.max_overlap = std::max(out.max_overlap, -c.gap);
    ++contact_count[c.i];
    if (!c.WithWall()) ++contact_count[c.j];
    out.contact_points.push_back(scene.particles[c.i].position + c.branch_i);
    out.contacts.push_back(std::move(c));
  }
  const int per_particle = out.frictional ? 3 : 2;
  const std::vector<int> first_row =
      NumberRows(scene, free, contact_count, per_particle, out.row_particle);
  const bool bath = scene.effects.pressure_bath.has_value();
  const int cell_row = static_cast<int>(out.row_particle.size());
  if (bath) out.row_particle.push_back(-1);

  // The cell row Σ f_n l·n = D V P_ext is scaled to read in units of the force scale F:
  // its residual over F is then the relative pressure mismatch.
  double mean_radius = 0.0;
  for (const Particle& p : scene.particles) mean_radius += p.radius / scene.particles.size();
  const double volume = scene.cell.size.x() * scene.cell.size.y();
  const double cell_row_scale = bath ? 2.0 * mean_radius / (kDimension * volume) : 1.0;
  std::vector<Eigen::Triplet<double>> t;
  const int stride = out.UnknownsPerContact();
  for (int k = 0; k < static_cast<int>(out.contacts.size()); ++k) {
    const Contact& c = out.contacts[k];
    const Vec2 tangent = Perp(c.normal);
    for (auto [particle, sign, arm] :
         {std::tuple{c.i, -1.0, c.branch_i.norm()},
          std::tuple{c.WithWall() ? -1 : c.j, 1.0, c.branch_j.norm()}}) {
      if (particle < 0 || first_row[particle] < 0) continue;
      const int row = first_row[particle];
      t.emplace_back(row, stride * k, sign * c.normal.x());
      t.emplace_back(row + 1, stride * k, sign * c.normal.y());
      if (!out.frictional) continue;
      t.emplace_back(row, stride * k + 1, sign * tangent.x());
      t.emplace_back(row + 1, stride * k + 1, sign * tangent.y());
      t.emplace_back(row + 2, stride * k + 1, -arm);
    }
    if (bath && !c.WithWall())
      t.emplace_back(cell_row, stride * k, cell_row_scale * c.center_to_center.dot(c.normal));
  }
  out.matrix.resize(static_cast<int>(out.row_particle.size()), out.NumUnknowns());
  out.matrix.setFromTriplets(t.begin(), t.end());

  out.load = Eigen::VectorXd::Zero(out.matrix.rows());
  double weight = 0.0;
  int weighed = 0;
  if (scene.effects.gravity) {
    for (std::size_t i = 0; i < scene.particles.size(); ++i) {
      if (first_row[i] < 0) continue;
      const Vec2 w = scene.particles[i].Mass() * *scene.effects.gravity;
      out.load[first_row[i]] = -w.x();
      out.load[first_row[i] + 1] = -w.y();
      weight += w.norm();
      ++weighed;
    }
  }
  if (bath) {
    const PressureBath& b = *scene.effects.pressure_bath;
    out.force_scale = 2.0 * mean_radius * b.pressure;
    out.load[cell_row] = out.force_scale;
  } else if (weighed > 0) {
    out.force_scale = weight / weighed;
  }
  return out;
}

Eigen::VectorXd StoredForcesOf(const EquilibriumSystem& system,
                               const std::vector<ContactForce>& stored) {
  const ForcesByContact lookup(stored);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(system.NumUnknowns());
  const int stride = system.UnknownsPerContact();
  for (int k = 0; k < static_cast<int>(system.contacts.size()); ++k) {
    const ContactForce* it = lookup.Find(system.contacts[k]);
    if (it == nullptr) continue;
    f[stride * k] = it->normal;
    if (system.frictional) f[stride * k + 1] = it->tangential;
  }
  return f;
}

std::vector<ContactForce> ToContactForces(const EquilibriumSystem& system,
                                          const Eigen::VectorXd& forces) {
  std::vector<ContactForce> out;
  const int stride = system.UnknownsPerContact();
  for (int k = 0; k < static_cast<int>(system.contacts.size()); ++k) {
    const double fn = forces[stride * k];
    const double ft = system.frictional ? forces[stride * k + 1] : 0.0;
    if (fn == 0.0 && ft == 0.0) continue;
    const Contact& c = system.contacts[k];
    out.push_back({c.i, c.j, c.image, fn, ft});
  }
  return out;
}

}  // namespace unjam
