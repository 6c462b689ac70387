#include "unjam/stepping/simulation.hpp"

#include <algorithm>
#include <cmath>

#include "unjam/problem/kinematics.hpp"

namespace unjam {

Simulation::Simulation(Scene scene, StepOptions options)
    : scene_(std::move(scene)), options_(std::move(options)),
      solver_(MakeSolver(options_.backend)) {
  Validate(options_.solver);
  if (!(options_.dt > 0.0)) throw std::invalid_argument("time step dt must be positive");
  if (!(options_.margin >= 0.0)) throw std::invalid_argument("detection margin must be >= 0");
}

// A pair can only close within the step if its approach speed times Δt exceeds its gap.
double Simulation::DetectionMargin() const {
  double fastest = 0.0;
  for (const Particle& p : scene_.particles) {
    fastest = std::max(fastest, p.velocity.norm() + p.radius * std::abs(p.spin));
  }
  if (scene_.effects.gravity) fastest += options_.dt * scene_.effects.gravity->norm();
  for (const PrescribedMotion& m : scene_.effects.prescribed_motion) {
    fastest = std::max(fastest, m.velocity.norm() + std::abs(m.spin));
  }
  if (const auto& bath = scene_.effects.pressure_bath) {
    // The cell may start to shrink within the step: λ_free = λ + Δt (P_kin − P_ext)/M_λ.
    const double rate =
        std::abs(bath->strain_rate) + options_.dt * bath->pressure / bath->cell_mass;
    fastest += rate * scene_.cell.size.maxCoeff();
  }
  return std::max(options_.margin, 4.0 * options_.dt * fastest);
}

Eigen::VectorXd Simulation::WarmStart(const AssembledProblem& assembled,
                                      const std::vector<Contact>& contacts) const {
  const ContactProblem& p = assembled.problem;
  Eigen::VectorXd guess = Eigen::VectorXd::Zero(p.NumUnknowns());
  // Both lists are sorted by key: merge.
  std::size_t old = 0;
  for (int k = 0; k < p.NumContacts(); ++k) {
    const Contact& c = contacts[assembled.source_contact[k]];
    while (old < contacts_.size() && ContactKeyLess(contacts_[old], c)) ++old;
    if (old < contacts_.size() && SameContactKey(contacts_[old], c)) {
      guess[k * p.UnknownsPerContact()] = impulses_[old][0];
      if (p.frictional) guess[2 * k + 1] = impulses_[old][1];
    }
  }
  return guess;
}

StepReport Simulation::Step() {
  std::vector<Contact> contacts = DetectContacts(scene_, DetectionMargin());
  EnsurePrescribedContacts(scene_, contacts);
  AssemblyOptions assembly;
  assembly.dt = options_.dt;
  assembly.overlap_correction = options_.overlap_correction;
  AssembledProblem assembled = AssembleProblem(scene_, contacts, assembly);
  const SolverGuess warm_start{WarmStart(assembled, contacts), {}};

  StepReport report;
  SolveResult result = solver_->Solve(assembled.problem, options_.solver, warm_start);
  report.solve = result.report;
  report.contacts = assembled.problem.NumContacts();

  // Keep impulses per detected contact (zero for the ones left out of the problem).
  impulses_.assign(contacts.size(), Eigen::Vector2d::Zero());
  const int stride = assembled.problem.UnknownsPerContact();
  for (int k = 0; k < assembled.problem.NumContacts(); ++k) {
    Eigen::Vector2d r(result.impulses[k * stride],
                      stride == 2 ? result.impulses[k * stride + 1] : 0.0);
    impulses_[assembled.source_contact[k]] = r;
    if (r[0] != 0.0) ++report.active_contacts;
  }
  contacts_ = std::move(contacts);
  Integrate(assembled, result.impulses);

  for (const Particle& q : scene_.particles) {
    if (!q.fixed)
      report.kinetic_energy +=
          0.5 * q.Mass() * q.velocity.squaredNorm() + 0.5 * q.Inertia() * q.spin * q.spin;
  }
  return report;
}

void Simulation::Integrate(const AssembledProblem& assembled, const Eigen::VectorXd& impulses) {
  const ContactProblem& p = assembled.problem;
  const VelocityState v = EndVelocityState(p, impulses);
  const double dt = options_.dt;
  const double rate = p.cell ? v.cell_rate : 0.0;
  const double stretch = 1.0 + dt * rate;
  for (int b = 0; b < p.NumBodies(); ++b) {
    Particle& q = scene_.particles[assembled.particle_of_body[b]];
    q.velocity = v.body[b].head<2>();
    if (p.frictional) q.spin = v.body[b][2];
  }
  for (const PrescribedMotion& m : scene_.effects.prescribed_motion) {
    scene_.particles[m.particle].velocity = m.velocity;
    scene_.particles[m.particle].spin = m.spin;
  }
  for (Particle& q : scene_.particles) {
    if (q.fixed) continue;
    q.position = stretch * q.position + dt * q.velocity;
    q.angle += dt * q.spin;
  }
  if (p.cell) {
    scene_.cell.size *= stretch;
    scene_.effects.pressure_bath->strain_rate = rate;
  }
  WrapPositions(scene_);
}

std::vector<ContactForce> Simulation::WarmStartImpulses() const {
  std::vector<ContactForce> out;
  for (std::size_t k = 0; k < contacts_.size(); ++k) {
    if (impulses_[k][0] == 0.0 && impulses_[k][1] == 0.0) continue;
    out.push_back(
        {contacts_[k].i, contacts_[k].j, contacts_[k].image, impulses_[k][0], impulses_[k][1]});
  }
  return out;
}

void Simulation::RestoreWarmStart(const std::vector<ContactForce>& impulses) {
  std::vector<ContactForce> sorted = impulses;
  std::sort(sorted.begin(), sorted.end(), ForceKeyLess);  // the order WarmStart merges in
  contacts_.clear();
  impulses_.clear();
  for (const ContactForce& f : sorted) {
    Contact c;  // only the key matters to the warm start
    c.i = f.i;
    c.j = f.j;
    c.image = f.image;
    contacts_.push_back(c);
    impulses_.emplace_back(f.normal, f.tangential);
  }
}

std::vector<ContactForce> LastStepForces(const Simulation& sim) {
  std::vector<ContactForce> forces = sim.WarmStartImpulses();
  const double dt = sim.options().dt;
  for (ContactForce& f : forces) {
    f.normal /= dt;
    f.tangential /= dt;
  }
  return forces;
}

double MaxOverlap(const Scene& scene) {
  double overlap = 0.0;
  for (const Contact& c : DetectContacts(scene, 0.0)) overlap = std::max(overlap, -c.gap);
  return overlap;
}

}  // namespace unjam
