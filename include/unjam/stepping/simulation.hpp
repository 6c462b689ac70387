// Moreau–Jean contact dynamics: one implicit (end-of-step velocity) step at a time.
//
// Stages of a step (names used in the code):
//   1. DetectContacts   candidate pairs whose gap may close within the step
//   2. Assemble         scene + contacts → ContactProblem (effects become terms)
//   3. WarmStart        impulses of the previous step, matched by (i, j, image)
//   4. Solve            the configured backend
//   5. Integrate        v⁺ = v_free + M⁻¹ Hᵀ r;  x⁺ = x(1 + Δt λ⁺) + Δt v⁺;  L⁺ = L(1 + Δt λ⁺)
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "unjam/contacts/contact.hpp"
#include "unjam/problem/assembly.hpp"
#include "unjam/scene/scene.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

struct StepOptions {
  double dt = 1e-3;
  double overlap_correction = 1.0;  // see AssemblyOptions
  // Contacts are detected up to gap < max(margin, 2 Δt · (largest approach speed)).
  double margin = 1e-6;
  std::string backend = "nsgs";
  SolverOptions solver;
};

struct StepReport {
  SolveReport solve;
  int contacts = 0;             // contacts in the problem
  int active_contacts = 0;      // with a non-zero normal impulse
  double kinetic_energy = 0.0;  // of the free particles, end of step
};

class Simulation {
 public:
  // Throws std::invalid_argument for an unknown backend or invalid options.
  Simulation(Scene scene, StepOptions options);

  StepReport Step();

  const Scene& scene() const { return scene_; }
  Scene& mutable_scene() { return scene_; }
  const StepOptions& options() const { return options_; }
  // Solver options may change between steps (tolerance schedules); the backend may not.
  StepOptions& mutable_options() { return options_; }
  // The warm start of the next step: the last step's non-zero impulses (not forces), keyed
  // by contact, and its replacement (a checkpoint saves and restores it exactly).
  std::vector<ContactForce> WarmStartImpulses() const;
  void RestoreWarmStart(const std::vector<ContactForce>& impulses);
  // Contacts of the last step (start-of-step geometry) and their impulses (n, t).
  const std::vector<Contact>& contacts() const { return contacts_; }
  const std::vector<Eigen::Vector2d>& impulses() const { return impulses_; }

 private:
  double DetectionMargin() const;
  Eigen::VectorXd WarmStart(const AssembledProblem& assembled,
                            const std::vector<Contact>& contacts) const;
  void Integrate(const AssembledProblem& assembled, const Eigen::VectorXd& impulses);

  Scene scene_;
  StepOptions options_;
  std::unique_ptr<ContactSolver> solver_;
  std::vector<Contact> contacts_;
  std::vector<Eigen::Vector2d> impulses_;
};

// Forces (impulse / Δt) of the last step's force-carrying contacts.
std::vector<ContactForce> LastStepForces(const Simulation& simulation);

// Largest overlap (−gap, ≥ 0) over all pairs of the scene, found with the broad phase.
double MaxOverlap(const Scene& scene);

}  // namespace unjam
