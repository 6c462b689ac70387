// The force ensemble (equilibrium_system.hpp) as the rows, columns and bounds of a linear
// program over f / F (F the force scale, so that solver tolerances are relative): rows
// A f = b / F, then per frictional contact ±f_t − μ f_n ≤ 0; columns f_n ≥ 0, f_t free.
// The one description that the nearest-network LP, the bounds (CLP) and Ipopt all load.
// Internal to src/indeterminacy.
#pragma once

#include <memory>
#include <vector>

#include <ClpSimplex.hpp>

#include "unjam/indeterminacy/equilibrium_system.hpp"
#include "unjam/indeterminacy/force_bounds.hpp"
#include "unjam/lp/lp_triplets.hpp"

namespace unjam::indeterminacy_internal {

using lp::LpTriplets;

LpTriplets EnsembleLp(const EquilibriumSystem& system);

// A CLP model of the ensemble with a zero objective (not yet solved).
std::unique_ptr<ClpSimplex> EnsembleModel(const EquilibriumSystem& system, double tolerance);

// The bound a finished CLP run proves: its optimum (sign · objective · scale), unbounded or
// infeasible; kFailed otherwise.
Bound Outcome(ClpSimplex& model, double sign, double scale);

// Runs one simplex (the dual first, or the primal), from the model's current basis, with
// CLP's start/finish options `keep`. With `confirm`, an outcome other than optimal is
// confirmed from the slack basis with the other simplex before it is believed: CLP's dual
// simplex has reported a feasible pile ensemble infeasible from the slack basis (free
// tangential columns, degenerate duals). The bounds confirm min and max of a feasible
// ensemble always; the infeasibility of max_without_friction, found by the dual simplex
// from an optimal basis after one bound is fixed, is common (hundreds of contacts per
// packing) and is not.
void Simplex(ClpSimplex& model, bool dual_first, int keep, bool confirm, long long& iterations);

}  // namespace unjam::indeterminacy_internal
