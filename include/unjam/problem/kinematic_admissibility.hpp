// Is any motion at all compatible with a step's non-penetration? A linear program over the
// generalised velocity v alone, with no forces and no inertia:
//     find v  with  ũ_n,k = (H v + offset)_n,k ≥ 0 (unilateral),  = 0 (bilateral),
// tangential velocities free (a contact may always slide). Every solution of the step's
// complementarity problem has such a v, so if this LP is infeasible the step has no
// solution: the prescribed motion or held gap is blocked by the rigid grains. Example: a
// contact of a frictionless packing in a frozen periodic cell. Its static forces f⁰ are a
// self-stress there (every grain is balanced, and no load acts), so by virtual work
// f⁰·ũ_n = 0 for every motion. Opening contact K (ũ_n,K > 0) would then need another
// carrying contact to close (ũ_n,j < 0): no opening is possible without penetration.
//
// The LP is posed in units of the largest normal offset: the perturbation ξ/Δt, or an open
// contact's gap over Δt (at most the detection margin, 1e-6 or 1000 ξ, for perturbations).
// CLP's feasibility tolerance (1e-9 here) is then relative to it, and a step that the
// solvers satisfy only by spreading sub-tolerance penetrations over many contacts is
// caught: at N = 500 those penetrations are 1e-3 of ξ each.
#pragma once

#include <string>

#include "unjam/problem/contact_problem.hpp"

namespace unjam {

struct KinematicAdmissibility {
  bool admissible = true;
  bool decided = true;  // false: CLP stopped without a verdict (then `admissible` stays true)
  std::string message;  // CLP's status when not admissible or not decided
};

KinematicAdmissibility CheckKinematicAdmissibility(const ContactProblem& problem);

}  // namespace unjam
