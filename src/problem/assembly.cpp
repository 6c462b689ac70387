#include "unjam/problem/assembly.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace unjam {

namespace {

// Bodies: free, non-prescribed particles. Prescribed particles have a known velocity.
void NumberBodies(const Scene& scene, AssembledProblem& out) {
  const int n = static_cast<int>(scene.particles.size());
  out.body_of_particle.assign(n, -1);
  std::vector<char> prescribed(n, 0);
  for (const PrescribedMotion& m : scene.effects.prescribed_motion) {
    if (m.particle < 0 || m.particle >= n)
      throw std::invalid_argument("prescribed motion names particle " + std::to_string(m.particle) +
                                  ", which does not exist");
    prescribed[m.particle] = 1;
  }
  for (int i = 0; i < n; ++i) {
    if (scene.particles[i].fixed || prescribed[i]) continue;
    out.body_of_particle[i] = static_cast<int>(out.particle_of_body.size());
    out.particle_of_body.push_back(i);
  }
}

void FillBodies(const Scene& scene, double dt, AssembledProblem& out) {
  ContactProblem& p = out.problem;
  const int nb = static_cast<int>(out.particle_of_body.size());
  p.inv_mass.resize(nb);
  p.free_velocity.resize(nb);
  if (p.frictional) {
    p.inv_inertia.resize(nb);
    p.free_spin.resize(nb);
  }
  for (int b = 0; b < nb; ++b) {
    const Particle& q = scene.particles[out.particle_of_body[b]];
    p.inv_mass[b] = 1.0 / q.Mass();
    p.free_velocity[b] = q.velocity;
    if (scene.effects.gravity) p.free_velocity[b] += dt * *scene.effects.gravity;
    if (p.frictional) {
      p.inv_inertia[b] = 1.0 / q.Inertia();
      p.free_spin[b] = q.spin;
    }
  }
}

// λ⁺ = λ + Δt (P_kin − P_ext)/M_λ + Σ_k c_k r_n,k / (M_λ D V): the barostat in impulse form.
void FillCell(const Scene& scene, double dt, AssembledProblem& out) {
  const PressureBath& bath = *scene.effects.pressure_bath;
  const double volume = scene.cell.size.x() * scene.cell.size.y();
  double kinetic = 0.0;
  for (int i : out.particle_of_body) {
    const Particle& q = scene.particles[i];
    kinetic += q.Mass() * q.velocity.squaredNorm();
  }
  const double kinetic_pressure = kinetic / (kDimension * volume);
  CellDof cell;
  cell.inv_mass = 1.0 / CellInertia(scene);
  cell.free_rate = bath.strain_rate + dt * (kinetic_pressure - bath.pressure) / bath.cell_mass;
  out.problem.cell = cell;
}

// Velocity of a side without degrees of freedom at the contact point: (v, ω).
std::pair<Vec2, double> KnownMotion(const Scene& scene, int particle) {
  for (const PrescribedMotion& m : scene.effects.prescribed_motion) {
    if (m.particle == particle) return {m.velocity, m.spin};
  }
  return {Vec2::Zero(), 0.0};  // fixed disks and walls do not move
}

const PrescribedGap* FindPrescribedGap(const Scene& scene, const Contact& c) {
  for (const PrescribedGap& g : scene.effects.prescribed_gaps) {
    if (g.i == c.i && g.j == c.j && g.image == c.image) return &g;
    if (g.i == c.j && g.j == c.i && g.image[0] == -c.image[0] && g.image[1] == -c.image[1])
      return &g;
  }
  return nullptr;
}

ProblemContact MakeProblemContact(const Scene& scene, const Contact& c, const AssembledProblem& out,
                                  const AssemblyOptions& options) {
  ProblemContact pc;
  pc.body_i = out.body_of_particle[c.i];
  pc.body_j = c.WithWall() ? -1 : out.body_of_particle[c.j];
  pc.normal = c.normal;
  pc.arm_i = c.branch_i.norm();
  pc.arm_j = c.branch_j.norm();
  pc.cell_arm = out.problem.cell && !c.WithWall() ? c.center_to_center.dot(c.normal) : 0.0;
  pc.mu = scene.effects.friction;
  const Vec2 t = Perp(c.normal);
  if (pc.body_i < 0) {
    const auto [v, w] = KnownMotion(scene, c.i);
    pc.bias += Vec2(-c.normal.dot(v), -t.dot(v) - pc.arm_i * w);
  }
  if (pc.body_j < 0 && !c.WithWall()) {
    const auto [v, w] = KnownMotion(scene, c.j);
    pc.bias += Vec2(c.normal.dot(v), t.dot(v) - pc.arm_j * w);
  }
  double gap = c.gap;
  if (std::abs(gap) <= options.closed_gap_tolerance) gap = 0.0;
  if (const PrescribedGap* held = FindPrescribedGap(scene, c)) {
    pc.kind = ConstraintKind::kBilateral;
    pc.mu = 0.0;
    pc.target_velocity = (held->gap - gap) / options.dt;
  } else {
    const double corrected = gap >= 0.0 ? gap : options.overlap_correction * gap;
    pc.target_velocity = -corrected / options.dt;
  }
  return pc;
}

// Whether the known motions of a contact's two sides (fixed, prescribed or a wall) violate
// its constraint within the step (close it beyond its gap, or move a held gap): the normal
// velocity they give it is its bias, the one it needs its target (MakeProblemContact).
// `out`: the problem so far, in which neither side has degrees of freedom.
bool ViolatesImmovable(const Scene& scene, const Contact& c, const AssembledProblem& out,
                       const AssemblyOptions& options) {
  const ProblemContact pc = MakeProblemContact(scene, c, out, options);
  const double given = pc.bias.x();
  const double slack = options.closed_gap_tolerance / options.dt + 1e-12 * std::abs(given);
  if (pc.kind == ConstraintKind::kBilateral) return std::abs(given - pc.target_velocity) > slack;
  // An overlap the sides already had (target above 0) is not the motion's doing.
  return given < std::min(pc.target_velocity, 0.0) - slack;
}

}  // namespace

AssembledProblem AssembleProblem(const Scene& scene, const std::vector<Contact>& contacts,
                                 const AssemblyOptions& options) {
  if (!(options.dt > 0.0)) throw std::invalid_argument("time step must be positive");
  AssembledProblem out;
  ContactProblem& p = out.problem;
  p.dt = options.dt;
  p.frictional = scene.effects.Frictional();
  NumberBodies(scene, out);
  FillBodies(scene, options.dt, out);
  if (scene.effects.pressure_bath) FillCell(scene, options.dt, out);
  p.contacts.reserve(contacts.size());
  out.source_contact.reserve(contacts.size());
  // Against gravity, for NSGS's height order (ProblemContact::height).
  std::optional<Vec2> up;
  if (scene.effects.gravity && scene.effects.gravity->norm() > 0.0)
    up = -scene.effects.gravity->normalized();
  for (int k = 0; k < static_cast<int>(contacts.size()); ++k) {
    const Contact& c = contacts[k];
    const bool i_moves = out.body_of_particle[c.i] >= 0;
    const bool j_moves = !c.WithWall() && out.body_of_particle[c.j] >= 0;
    const bool cell_moves = p.cell && !c.WithWall();
    if (!i_moves && !j_moves && !cell_moves) {
      if (ViolatesImmovable(scene, c, out, options)) out.violated_immovable.push_back(k);
      continue;
    }
    p.contacts.push_back(MakeProblemContact(scene, c, out, options));
    if (up) p.contacts.back().height = up->dot(scene.particles[c.i].position + c.branch_i);
    out.source_contact.push_back(k);
  }
  return out;
}

std::string DescribeImmovableViolation(const Contact& c) {
  return "the known motions close the contact of particle " + std::to_string(c.i) + " and " +
         (c.WithWall() ? std::string("a wall") : "particle " + std::to_string(c.j)) +
         ", neither of which can give way (the step penetrates there)";
}

void EnsurePrescribedContacts(const Scene& scene, std::vector<Contact>& contacts) {
  const int n = static_cast<int>(scene.particles.size());
  for (const PrescribedGap& g : scene.effects.prescribed_gaps) {
    if (g.i < 0 || g.i >= n || g.j < 0 || g.j >= n || g.i == g.j) {
      throw std::invalid_argument("prescribed gap names particles " + std::to_string(g.i) + ", " +
                                  std::to_string(g.j) + ": no such pair");
    }
    Contact c = g.i < g.j ? MakeContact(scene, g.i, g.j, g.image)
                          : MakeContact(scene, g.j, g.i, {-g.image[0], -g.image[1]});
    auto it = std::lower_bound(contacts.begin(), contacts.end(), c, ContactKeyLess);
    if (it == contacts.end() || !SameContactKey(*it, c)) contacts.insert(it, c);
  }
}

}  // namespace unjam
