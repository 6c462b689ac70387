// The response of a static packing of rigid grains to an infinitesimal perturbation (a
// contact held open by ξ, a grain moved by ξ), as the rigid limit of stiff contacts: the
// quasi-rigid loading path (McNamara & Herrmann, "Quasirigidity: some uniqueness issues",
// PRE 2006). docs/perturbations.md, "How a perturbation is solved".
//
// Every contact gets the same compliance δ in both directions. The forces stay in
// equilibrium, so they change only by self-stresses: r = r₀ + S α (self_stress.hpp, S
// orthonormal). A contact sticks, slides (Coulomb: its force on an edge of the cone, the
// slip along its tangent, opposite to the friction force) or opens (no force). The plastic
// displacement u of the contacts that slide or open and the prescribed displacement t·d
// (the perturbation, t its size) are compatible with rigid grains up to the elastic part:
//     α = α₀ + P (Σ_c G_c u_c + t d) / δ
// (P projects out the directions of the forces the perturbation releases, e.g. the held
// contact's friction, whose force must vanish). Taking δ = 1 sets the units of u and t.
// As t grows from 0, the contacts change state one at a time: the path is piecewise
// linear, and each piece is one small dense linear system (one unknown per slip, two per
// open contact). Far along the path the rigid limit shows: the forces stop changing while
// the opening goes on (a collapse mechanism forms that opens the perturbation: the critical
// force is reached) or they grow without bound (rigid grains cannot accommodate the
// perturbation: blocked).
//
// The path is holonomic (a contact's total slip is its state variable: it sticks again only
// where its slip returns to zero), the form whose end Lemke's method on the time step finds
// too. It may turn back in t (a snap-back of the stiff packing) and go on; it ends where
// its forces plateau as t → ∞. Degenerate events (several at the same point of the path)
// are taken one at a time in a fixed order; a state that comes back ends the path
// (kCycle).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "unjam/solvers/pattern_polish.hpp"

namespace unjam {

// One closed contact of the rate problem: its rows of the basis (normal, tangential; −1
// without friction), its friction coefficient and static impulses.
struct RateContact {
  int row_n = -1;
  int row_t = -1;
  double mu = 0.0;
  double r0_n = 0.0, r0_t = 0.0;
  // The perturbation's own contact (the held one): no contact law, it is not checked.
  bool held = false;
};

struct RateProblem {
  Eigen::MatrixXd basis;  // S: unknowns × D, orthonormal columns
  std::vector<RateContact> contacts;
  // Rows of S whose force the perturbation releases to zero (the held contact's friction):
  // their forces are brought to zero first (phase 1), then stay there.
  std::vector<int> released_rows;
  Eigen::VectorXd driver;  // d = Sᵀ(prescribed relative displacement per unit t)

  // The static impulse of a row of S (a contact's normal or tangential one; 0 for a row
  // that is no contact's, e.g. a released balance).
  double StaticImpulse(int row) const;
};

enum class RatePathEnd {
  kCollapse,       // the forces plateau as t → ∞: the rigid limit, a quasi-static response
  kUnbounded,      // the forces grow without bound with t: rigid grains block it
  kReleaseFails,   // the released forces cannot be brought to zero along the path
  kFixedCollapse,  // a mechanism grows with t fixed: the packing gives way elsewhere
  kBack,           // the path returned to t = 0
  kCycle,          // a state came back
  kStalled,        // work or event limit (RatePathOptions)
  kSingular,       // a piece's linear system lost rank
};
const char* ToString(RatePathEnd end);

struct RatePathResult {
  RatePathEnd end = RatePathEnd::kStalled;
  Eigen::VectorXd alpha;  // forces at the end: r = r₀ + S α
  std::vector<ContactState> states;
  // Per contact, the plastic velocity of the last piece per unit t (the mechanism per unit
  // perturbation at a collapse): (normal opening, tangential slip).
  std::vector<Eigen::Vector2d> rates;
  Eigen::VectorXd alpha_rate;     // dα/dt on the last piece
  double t = 0.0;                 // where the path ended
  int events = 0;                 // state changes
  double work = 0.0;              // multiply-adds of its pieces, as RatePathOptions counts them
  int turns = 0;                  // reversals of t
  int free_mechanism_pieces = 0;  // pieces taken beside free mechanisms (a spinning grain)
  int pieces_oriented_by_t = 0;   // pieces on which the released quantity did not move
  std::string message;
};

// A path ends `stalled` when its work or its events reach these limits. An event counts
// rows(S) × D + m² multiply-adds (the forces' change S dα over every contact, the QR
// update; m the unknowns of the piece), a nominal count: the ratio test reads only the
// contacts near a bound (reach_heap.hpp). The work limit is about 6 000 events of the 1600-disk
// pile at μ = 0.1 (S 5 840 × 1 057, m ≈ 800; a minute or so; its bottom shift 387 collapses after
// 5 042), where a cheaper path may take more events, e.g. 35 000 on the μ = 1 pile (S about
// 5 000 × 200). Both limits are fixed counts, so a path ends the same way on every machine.
struct RatePathOptions {
  double max_work = 4e10;
  int max_events = 200000;
  // The ratio test reads every contact at every event instead of those near a bound (a
  // cross-check of reach_heap.hpp's pruning: the same path, event for event).
  bool read_every_contact = false;
};

RatePathResult FollowRatePath(const RateProblem& problem, const RatePathOptions& options = {});

}  // namespace unjam

namespace unjam {

// The static LP of a rate problem: is there a network of admissible forces (every contact
// but the held one in its Coulomb cone, r_n ≥ 0) in which the released forces vanish? In
// the basis' coordinates: D free variables α, two rows per frictional contact (one
// without friction) and one per released force (COIN-OR CLP). Solved by cutting planes:
// first over the 4D rows nearest to binding at the static forces (a relaxation: no
// feasible point there proves none exists), then with the rows its point violates added,
// up to 8 rounds, then over every row. An infeasibility found by the dual simplex counts
// only with a Farkas certificate checked in double precision. Where there is no network,
// no static network holds the perturbed packing: the step is dynamic whatever else
// happens (docs/perturbations.md).
struct RateStaticLp {
  bool decided = false;  // CLP ended optimal or proven infeasible
  bool feasible = false;
  int iterations = 0;
  std::string message;
};
struct RateStaticLpOptions {
  bool every_row = false;  // skip the cutting planes: one LP over every row (a cross-check)
};
RateStaticLp SolveRateStaticLp(const RateProblem& problem, const RateStaticLpOptions& options = {});

}  // namespace unjam
