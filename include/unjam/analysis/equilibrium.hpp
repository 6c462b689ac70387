// Force and torque balance of a static state, and the internal stress (virial).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "unjam/contacts/contact.hpp"
#include "unjam/scene/scene.hpp"

namespace unjam {

// A static answer whose EquilibriumReport::residual exceeds this is not in equilibrium to
// the accuracy a converged solve at the default tolerance gives a well-conditioned problem
// (1e-10): the state is not static, or the problem is ill-conditioned (docs/residual.md).
inline constexpr double kStaticEquilibriumTolerance = 1e-8;

struct EquilibriumReport {
  double mean_contact_force = 0.0;    // mean f_n over force-carrying contacts
  double max_force_imbalance = 0.0;   // max over free particles |F_ext + Σ f| / mean f_n
  double max_torque_imbalance = 0.0;  // max |Σ torque| / (mean f_n · mean radius)
  int worst_particle = -1;
  double residual = 0.0;  // max of the two imbalances
  double pressure = 0.0;  // virial Σ f·l / (D V) (fully periodic cells), else 0
  int force_carrying_contacts = 0;
};

// `forces[k]` = (f_n, f_t) of contacts[k], acting on j (minus on i). Particles with
// prescribed motion and fixed particles are not required to balance.
EquilibriumReport CheckEquilibrium(const Scene& scene, const std::vector<Contact>& contacts,
                                   const std::vector<Eigen::Vector2d>& forces);

// Coordination z = 2 N_c / N' (N_c force-carrying contacts between free particles,
// N' the free particles carrying force, rattlers excluded): the mean number of force-
// carrying contacts of a non-rattler. A contact with a fixed disk or a wall counts
// for the free particle only.
struct Coordination {
  double z = 0.0;                // contacts per particle that carries force (rattlers excluded)
  double z_with_rattlers = 0.0;  // contacts per free particle, rattlers included
  int rattlers = 0;              // free particles without any force-carrying contact
  int force_carrying_contacts = 0;
};
Coordination ComputeCoordination(const Scene& scene, const std::vector<Contact>& contacts,
                                 const std::vector<Eigen::Vector2d>& forces);
// The same from forces stored with a scene. In both, a contact carries force when f_n is
// above CarryingThreshold (scene.hpp).
Coordination ComputeCoordination(const Scene& scene, const std::vector<ContactForce>& forces);

}  // namespace unjam
