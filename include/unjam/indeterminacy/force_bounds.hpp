// Bounds of the admissible normal force of each contact, and the degree of force
// indeterminacy (docs/indeterminacy.md).
//
// The ensemble: every f with A f = b, f_n ≥ 0, |f_t| ≤ μ f_n (equilibrium_system.hpp). Per
// contact k, three linear programs over it:
//   min f_n,k        max f_n,k        max f_n,k subject to f_t,k = 0
// (the last: the largest load the contact can carry while transmitting no tangential force,
// the load of a pure opening). The constraints are the same for every contact and only the
// objective changes, so one COIN-OR CLP model is kept and re-optimised by the primal
// simplex from the previous optimal basis (which stays primal feasible): a warm start.
//
// The degree of indeterminacy is dim ker A = unknowns − rank A, the rank from SuiteSparseQR
// (rank-revealing sparse QR) with the tolerance below.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "unjam/indeterminacy/equilibrium_system.hpp"

namespace unjam {

enum class BoundStatus { kOptimal, kUnbounded, kInfeasible, kFailed };
const char* ToString(BoundStatus status);
std::optional<BoundStatus> BoundStatusFromString(const std::string& name);

struct Bound {
  BoundStatus status = BoundStatus::kFailed;
  double value = 0.0;  // meaningful only when status is kOptimal
  bool ok() const { return status == BoundStatus::kOptimal; }
};

// The three LPs of a contact, in the order a block of contacts runs them.
enum class BoundKind { kMax, kMaxWithoutFriction, kMin };
const char* ToString(BoundKind kind);
std::optional<BoundKind> BoundKindFromString(const std::string& name);

struct ContactBounds {
  int contact = -1;        // index into EquilibriumSystem::contacts
  double reference = 0.0;  // f_n of the reference (stored) forces
  Bound min, max, max_without_friction;
  Bound& Of(BoundKind kind) {
    return kind == BoundKind::kMin ? min : kind == BoundKind::kMax ? max : max_without_friction;
  }
  const Bound& Of(BoundKind kind) const {
    return kind == BoundKind::kMin ? min : kind == BoundKind::kMax ? max : max_without_friction;
  }
};

// One bound as it was obtained: what a long run writes as it goes and resumes from
// (`unjam bounds -o`, docs/indeterminacy.md, "Long runs").
struct BoundRecord {
  int contact = -1;  // index into EquilibriumSystem::contacts
  BoundKind kind = BoundKind::kMax;
  Bound bound;
  long long iterations = 0;  // simplex iterations of its LP (0 for a shortcut)
  bool shortcut = false;     // answered by an earlier optimal network, no LP
};

enum class LpBackend { kClp, kIpopt };
const char* ToString(LpBackend backend);
LpBackend LpBackendFromString(const std::string& name);  // throws std::invalid_argument

struct BoundsOptions {
  // CLP (exact simplex, warm-started) or Ipopt (interior point, every LP from scratch; one
  // thread: Ipopt with sequential MUMPS is not thread-safe). The feasibility check of the
  // ensemble is CLP's in both cases.
  LpBackend lp = LpBackend::kClp;
  bool warm_start = true;  // CLP: false = every LP from the slack basis (for comparison)
  double lp_tolerance =
      1e-10;        // CLP primal and dual tolerances, Ipopt's tol; relative (forces / F)
  int threads = 1;  // contacts split in contiguous blocks, one model each
  // CLP: skip an LP whose answer an earlier optimal solution of the same block already
  // proves (min f_n,k = 0 when a network with f_n,k = 0 was seen; max without friction =
  // max when the maximising network has f_t,k = 0). false runs every LP (for comparison).
  bool shortcuts = true;
  // Long runs. Bounds already obtained (e.g. read back from an interrupted run's records)
  // are taken as they are, without an LP; every other bound is passed to `on_bound` as soon
  // as it exists (one call at a time, from any block's thread). No LP starts after
  // `start_before`: the report is then incomplete.
  std::vector<BoundRecord> known;
  std::function<void(const BoundRecord&)> on_bound;
  std::optional<std::chrono::steady_clock::time_point> start_before;
  // Processes sharing the contacts (`mpirun … unjam bounds`): the spatial order is cut into
  // threads × shares blocks and this process runs the `threads` blocks of share `share`. The
  // blocks are those of one process on threads × shares threads, so the bounds are the same
  // bit for bit. Only this share's bounds are filled in (and `complete` speaks of them).
  int shares = 1;
  int share = 0;
};

// The ensemble itself is infeasible when the stored state is not static: checked once.
struct BoundsReport {
  std::vector<ContactBounds> bounds;
  bool feasible = false;
  std::string message;  // why not, when infeasible
  double seconds = 0.0;
  long long lp_iterations = 0;  // simplex iterations over all LPs
  long long lps_skipped = 0;    // LPs answered by a shortcut (BoundsOptions::shortcuts)
  long long bounds_known = 0;   // taken from BoundsOptions::known
  bool complete = true;         // false: BoundsOptions::start_before stopped the run
};

// `contacts`: indices into system.contacts. `reference`: the system's unknowns (e.g. the
// stored forces), reported beside the bounds.
BoundsReport ComputeForceBounds(const EquilibriumSystem& system, const std::vector<int>& contacts,
                                const Eigen::VectorXd& reference,
                                const BoundsOptions& options = {});

// The report that `known` alone makes, without an LP (rank 0 of an mpirun, once the ranks'
// records are merged): every bound of `contacts` taken from `known`, the ensemble taken as
// feasible (a run records bounds only after its feasibility LP), `complete` when none is
// missing. A frictionless system's maximum without friction is its maximum, as
// ComputeForceBounds gives it.
BoundsReport BoundsFromRecords(const EquilibriumSystem& system, const std::vector<int>& contacts,
                               const Eigen::VectorXd& reference,
                               const std::vector<BoundRecord>& known);

struct Indeterminacy {
  int unknowns = 0;         // force components
  int equations = 0;        // balance rows
  int rank = 0;             // min of the estimates below and of the row identities
  int rank_of_a = 0;        // SuiteSparseQR of A (an upper estimate)
  int rank_transposed = 0;  // SuiteSparseQR of Aᵀ (an upper estimate)
  int dimension = 0;        // unknowns − rank
  double tolerance = 0.0;   // rank tolerance used
};
// Rank tolerance: 1e-10 × the largest column 2-norm of A (rows in force units: each entry is
// a direction cosine, a lever arm or a scaled cell arm), documented in docs/indeterminacy.md.
// The rank is the smallest of two SuiteSparseQR estimates (of A and of Aᵀ) and of the
// number of rows less their exact identities (translations of a periodic packing).
Indeterminacy ForceIndeterminacy(const EquilibriumSystem& system);

}  // namespace unjam
