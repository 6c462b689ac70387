// Stage 1 of the admissible-force certificate (admissible_forces.hpp): the least-squares
// correction of smallest norm that balances every particle while every contact keeps its
// region of the Coulomb cone. Internal to src/indeterminacy.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "unjam/indeterminacy/equilibrium_system.hpp"

namespace unjam::indeterminacy_internal {

enum class Region : std::uint8_t { kOff, kInside, kEdgePositive, kEdgeNegative };

// Edge: f_n > 0 and |f_t| ≥ μ f_n (1 − edge_tolerance); inside otherwise (also f_n ≤ 0:
// every closed contact may carry force until a correction says otherwise).
std::vector<Region> ClassifyRegions(const EquilibriumSystem& system, const Eigen::VectorXd& forces,
                                    double edge_tolerance);

// The least-squares correction within the regions, then an active-set loop: a contact whose
// normal force turns negative is switched off, one that leaves the cone is put on its edge,
// and the correction is redone, for at most `max_rounds` rounds. The admissible forces, or
// nothing if no round balances every particle to `tolerance` (relative to the force scale)
// inside the cones.
std::optional<Eigen::VectorXd> ProjectOntoAdmissible(const EquilibriumSystem& system,
                                                     const Eigen::VectorXd& reference,
                                                     std::vector<Region> regions, double tolerance,
                                                     int max_rounds = 20);

}  // namespace unjam::indeterminacy_internal
