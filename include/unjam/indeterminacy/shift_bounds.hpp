// Bounds of a particle shift's critical force over the admissible force networks: the
// linear-program counterpart of `unjam perturb --top / --bottom` (docs/indeterminacy.md,
// "Particle shifts").
//
// A shifted particle P moves by ξ along ŝ for one step (prescribed motion, perturbation.hpp).
// Whatever pushes it supplies its balance, so its rows leave the ensemble. Its contacts with
// fixed bodies (the bed, walls) that the shift opens carry no force after the step
// (Signorini). Every other grain balances within its Coulomb cones, as in force_bounds.hpp.
// Over the networks left, F_crit = −ŝ·Σ f (the contact forces on P, `perturb`'s definition)
// is linear in the forces, and its min and max are two linear programs.
//
// Whatever member of its family of solutions a solver picks, the F_crit of a quasi-static
// shift lies in [min, max] (up to its inertial part, of order ξ): its forces are such a
// network. An unbounded max means that some network resists any push. Without friction the
// shift is then blocked (by virtual work, no motion that penetrates nothing can move P along
// ŝ); with friction a sliding motion may still exist, and `perturb`'s kinematic check
// decides.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "unjam/indeterminacy/equilibrium_system.hpp"
#include "unjam/indeterminacy/force_bounds.hpp"

namespace unjam {

struct ShiftTarget {
  int particle = -1;
  Vec2 direction = Vec2(0.0, -1.0);  // ŝ, unit
};

struct ShiftBounds {
  ShiftTarget target;
  double reference = 0.0;     // F_crit of the reference forces (the stored network)
  int unloaded_contacts = 0;  // contacts with fixed bodies that the shift opens
  Bound min, max;
};

struct ShiftBoundsReport {
  std::vector<ShiftBounds> bounds;
  bool feasible = false;  // the ensemble of the unperturbed packing
  std::string message;    // why not, when infeasible
  double seconds = 0.0;
  long long lp_iterations = 0;
};

// CLP only (options.lp must be kClp): each shift's LPs start from the optimal basis of the
// unperturbed ensemble (or from the slack basis with options.warm_start = false); shifts are
// split among options.threads. `reference`: the system's unknowns (e.g. the stored forces).
ShiftBoundsReport ComputeShiftBounds(const EquilibriumSystem& system,
                                     const std::vector<ShiftTarget>& shifts,
                                     const Eigen::VectorXd& reference,
                                     const BoundsOptions& options = {});

}  // namespace unjam
