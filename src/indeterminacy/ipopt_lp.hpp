// The second LP backend of the force bounds: Ipopt (interior point, MUMPS) on the same
// linear program. Internal to src/indeterminacy. No warm start: every LP from scratch.
// Ipopt with sequential MUMPS is not thread-safe: the caller runs it on one thread.
#pragma once

#include "unjam/indeterminacy/force_bounds.hpp"

namespace unjam::indeterminacy_internal {

// Optimises sign · f_n of unknown `normal_column`, with f_t of `fixed_tangential` fixed at 0
// if ≥ 0. sign = +1: minimum, −1: maximum. Returns the bound (in force units).
Bound IpoptBound(const EquilibriumSystem& system, int normal_column, double sign,
                 int fixed_tangential, double tolerance, long long& iterations);

}  // namespace unjam::indeterminacy_internal
