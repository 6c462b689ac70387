// Scene + contacts → ContactProblem: the only place where the scene's effects become the
// terms of the contact problem. Effects the scene does not declare add nothing.
#pragma once

#include <string>
#include <vector>

#include "unjam/contacts/contact.hpp"
#include "unjam/problem/contact_problem.hpp"
#include "unjam/scene/scene.hpp"

namespace unjam {

struct AssemblyOptions {
  double dt = 1e-3;  // time step
  // Fraction of an existing overlap removed within the step (1 = all of it, so a closed
  // contact ends the step with a non-negative linearised gap).
  double overlap_correction = 1.0;
  // Gaps with |g| below this are treated as exactly closed (static solves), 0 = off.
  double closed_gap_tolerance = 0.0;
};

struct AssembledProblem {
  ContactProblem problem;
  std::vector<int> body_of_particle;  // −1: no degrees of freedom (fixed or prescribed)
  std::vector<int> particle_of_body;
  std::vector<int> source_contact;  // problem contact k is contacts[source_contact[k]]
  // Contacts left out (both sides without degrees of freedom) whose constraint the known
  // motion violates within the step: no impulse can change it (e.g. a prescribed particle
  // pushed into a fixed one penetrates it, whatever is solved).
  std::vector<int> violated_immovable;  // indices into contacts
};

// Contacts between two sides without degrees of freedom are left out (nothing can move);
// those whose constraint the known motion violates are listed (violated_immovable).
// Prescribed gaps (scene.effects.prescribed_gaps) turn their contact bilateral; the contact
// must be in `contacts` (see EnsurePrescribedContacts).
AssembledProblem AssembleProblem(const Scene& scene, const std::vector<Contact>& contacts,
                                 const AssemblyOptions& options);

// Why contact c is in violated_immovable, in words naming its particles (or the wall).
std::string DescribeImmovableViolation(const Contact& c);

// Adds the contacts named by prescribed gaps when detection did not find them (a gap
// larger than the margin), keeping the order. Throws std::invalid_argument for a
// prescribed gap naming a particle that does not exist.
void EnsurePrescribedContacts(const Scene& scene, std::vector<Contact>& contacts);

}  // namespace unjam
