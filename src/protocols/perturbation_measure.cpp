// What a solution of a perturbation's step measures: F_crit, the reference force, the
// displacements and their penetration depth, the force changes, the inertia, and whether
// the response is linear in ξ.
#include <algorithm>
#include <cmath>
#include <limits>

#include "perturbation_internal.hpp"
#include "unjam/analysis/equilibrium.hpp"

namespace unjam {
namespace perturbation_internal {

namespace {
Vec2 ForceVector(const Contact& c, const Eigen::Vector2d& f) {
  return f[0] * c.normal + f[1] * Perp(c.normal);
}

// Calls visit(f) with the force f that each contact exerts on particle p.
template <class Visit>
void ForEachForceOn(int p, const std::vector<Contact>& contacts,
                    const std::vector<Eigen::Vector2d>& forces, Visit visit) {
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    if (c.i == p) visit(Vec2(-ForceVector(c, forces[k])));
    if (!c.WithWall() && c.j == p) visit(ForceVector(c, forces[k]));
  }
}

// Σ of the contact forces acting on particle p.
Vec2 ContactForceOn(int p, const std::vector<Contact>& contacts,
                    const std::vector<Eigen::Vector2d>& forces) {
  Vec2 sum = Vec2::Zero();
  ForEachForceOn(p, contacts, forces, [&](const Vec2& f) { sum += f; });
  return sum;
}

}  // namespace

// Effective weight F_y: the sum of the positive vertical components of the contact forces
// on particle p.
double EffectiveWeight(int p, const std::vector<Contact>& contacts,
                       const std::vector<Eigen::Vector2d>& forces) {
  double sum = 0.0;
  ForEachForceOn(p, contacts, forces, [&](const Vec2& f) { sum += std::max(f.y(), 0.0); });
  return sum;
}

namespace {
std::vector<ContactForceChange> ForceChanges(const PerturbationBase& base,
                                             const StaticSolution& after) {
  std::vector<ContactForceChange> out;
  out.reserve(after.contacts.size());
  // Both lists are sorted by key (detection order); the perturbed one may hold one more
  // contact (a held gap beyond the margin).
  std::size_t a = 0;
  for (std::size_t b = 0; b < after.contacts.size(); ++b) {
    const Contact& c = after.contacts[b];
    while (a < base.contacts.size() && ContactKeyLess(base.contacts[a], c)) ++a;
    ContactForceChange change{c.i,      c.j,
                              c.image,  base.scene.particles[c.i].position + c.branch_i,
                              c.normal, c.center_to_center};
    if (a < base.contacts.size() && SameContactKey(base.contacts[a], c)) {
      change.normal_before = base.forces[a][0];
      change.tangential_before = base.forces[a][1];
    }
    change.normal_after = after.forces[b][0];
    change.tangential_after = after.forces[b][1];
    out.push_back(change);
  }
  return out;
}

double PenetrationDepth(const Scene& scene, const std::vector<Vec2>& d, Vec2 origin, Vec2 axis) {
  double weighted = 0.0, total = 0.0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double magnitude = d[i].norm();
    if (magnitude == 0.0) continue;
    const Vec2 r = MinimumImage(scene.cell, scene.particles[i].position - origin);
    weighted += magnitude * std::abs(r.dot(axis));
    total += magnitude;
  }
  return total > 0.0 ? weighted / total : 0.0;
}

// The force scale of each kind of degree of freedom: a grain's
// translation, the mean contact force; its spin, that force times its radius; the cell's
// strain, D V P_ext (the virial at the bath's pressure).
double TranslationScale(const PerturbationBase& base) {
  return base.mean_contact_force > 0.0 ? base.mean_contact_force : 1.0;
}
double CellScale(const Scene& scene) {
  const PressureBath& bath = *scene.effects.pressure_bath;
  return CellInertia(scene) / bath.cell_mass * bath.pressure;
}

// The largest inertial force of the answer over its scale: m_i |d_i| / Δt² of every grain,
// I_i |θ_i| / Δt² of every spin, and the cell's M_λ D V |ε| / Δt² under a pressure bath.
double InertiaRatio(const PerturbationBase& base, const PerturbationResult& r, double dt) {
  const double force = TranslationScale(base);
  double largest = 0.0;
  for (std::size_t i = 0; i < r.displacement.size(); ++i) {
    const Particle& p = base.scene.particles[i];
    largest = std::max(largest, p.Mass() * r.displacement[i].norm() / force);
    if (!r.rotation.empty())
      largest = std::max(largest, p.Inertia() * std::abs(r.rotation[i]) / (force * p.radius));
  }
  if (base.scene.effects.pressure_bath) {
    largest = std::max(largest,
                       CellInertia(base.scene) * std::abs(r.cell_strain) / CellScale(base.scene));
  }
  return largest / (dt * dt);
}

// The inertial work over the step, over ξ: grains, and the cell under a pressure bath (its
// strain ε = ΔL/L moves with mass M_λ D V, docs/method.md).
double InertialForce(const PerturbationBase& base, const PerturbationResult& r, double gap,
                     double dt) {
  double work = 0.0;
  for (std::size_t i = 0; i < r.displacement.size(); ++i) {
    const Particle& p = base.scene.particles[i];
    work +=
        p.Mass() * r.displacement[i].squaredNorm() + p.Inertia() * r.rotation[i] * r.rotation[i];
  }
  if (base.scene.effects.pressure_bath)
    work += CellInertia(base.scene) * r.cell_strain * r.cell_strain;
  return work / (gap * dt * dt);
}

// The largest displacement in units of ξ, at least 1: the solver tolerance is set for a
// response of size ξ, and a response n times larger is resolved by an n times larger one.
double ResponseSize(const std::vector<Vec2>& d, double gap) {
  double largest = 0.0;
  for (const Vec2& di : d) largest = std::max(largest, di.norm());
  return std::max(1.0, largest / gap);
}

}  // namespace

void SetOriginAndReference(const PerturbationBase& base, const PerturbationTarget& t,
                           PerturbationResult& r) {
  if (t.kind == PerturbationTarget::Kind::kParticleShift) {
    r.origin = base.scene.particles[t.i].position;
    r.axis = Vec2(0.0, 1.0);
    r.f_reference = EffectiveWeight(t.i, base.contacts, base.forces);
    return;
  }
  const int k = FindContact(base.contacts, t.i, t.j, t.image);
  const Contact c = k >= 0 ? base.contacts[k] : MakeContact(base.scene, t.i, t.j, t.image);
  r.origin = base.scene.particles[t.i].position + c.branch_i;
  r.axis = c.normal;
  r.f_reference = k >= 0 ? base.forces[k][0] : 0.0;
}

namespace {
double CriticalForce(const PerturbationTarget& t, const StaticSolution& s) {
  if (t.kind == PerturbationTarget::Kind::kParticleShift) {
    return 0.0 - t.direction.dot(
                     ContactForceOn(t.i, s.contacts, s.forces));  // +0, not −0, when nothing pushes
  }
  const int k = FindContact(s.contacts, t.i, t.j, t.image);
  return k >= 0 ? s.forces[k][0] : 0.0;
}

double LinearityMisfit(const std::vector<Vec2>& d, const std::vector<Vec2>& d_scaled,
                       double factor) {
  double largest = 0.0, misfit = 0.0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    largest = std::max(largest, d_scaled[i].norm());
    misfit = std::max(misfit, (d_scaled[i] - factor * d[i]).norm());
  }
  if (largest > 0.0) return misfit / largest;
  return misfit == 0.0
             ? 0.0
             : std::numeric_limits<double>::infinity();  // nothing moves at either gap: linear
}
}  // namespace

// What one solution of the step measures, into r (its target, origin and reference set).
void Measure(const PerturbationBase& base, const PerturbationOptions& options,
             const StaticSolveOptions& solve, const StaticSolution& s, PerturbationResult& r) {
  r.solve = s.report;
  r.f_crit = CriticalForce(r.target, s);
  r.displacement = s.displacement;  // the shifted particle's included: its shift
  r.rotation = s.rotation;
  r.cell_strain = s.cell_strain;
  r.force_changes = ForceChanges(base, s);
  r.penetration_depth = PenetrationDepth(base.scene, r.displacement, r.origin, r.axis);
  if (PeriodicY(base.scene.cell.periodicity))
    r.pressure_change = s.equilibrium.pressure - base.pressure;
  r.inertia_ratio = InertiaRatio(base, r, options.dt);
  r.inertial_force = InertialForce(base, r, options.gap, options.dt);
  r.equilibrium_residual = s.equilibrium.residual;
  r.quasi_static = r.inertia_ratio <= options.max_inertia_ratio;
  // The residual is relative to the solution's own force scale; a solution with runaway
  // forces (pushing into a rigid column) must not pass by inflating it.
  const double scale_ratio = base.mean_contact_force > 0.0
                                 ? s.equilibrium.mean_contact_force / base.mean_contact_force
                                 : 1.0;
  const double absolute = r.solve.residual * std::max(1.0, scale_ratio);
  r.resolved = absolute <= solve.solver.tolerance * ResponseSize(r.displacement, options.gap);
  r.status = !r.resolved       ? PerturbationStatus::kNotConverged
             : !r.quasi_static ? PerturbationStatus::kDynamic
                               : PerturbationStatus::kOk;
}

// Compares a quasi-static result r with the same perturbation at 10ξ (`scaled`).
void JudgeLinearity(const PerturbationBase& base, const PerturbationResult& scaled,
                    PerturbationResult& r) {
  r.fcrit_10xi = scaled.f_crit;
  r.linearity_misfit = LinearityMisfit(r.displacement, scaled.displacement, kLinearityGapFactor);
  r.linear = scaled.quasi_static && r.linearity_misfit <= kLinearityMisfit &&
             std::abs(scaled.f_crit - r.f_crit) <= kLinearityForceChange * base.mean_contact_force;
  if (!r.linear) r.status = PerturbationStatus::kNonlinear;
}

}  // namespace perturbation_internal
}  // namespace unjam
