// Run contact dynamics until the packing is static, and prove it.
//
// 1. Dynamics with a loose per-step tolerance and a budget of sweeps per step (contact
//    dynamics of dense packings is not solved tightly at every step: the sweeps needed grow
//    like (L/d)²).
// 2. Calm: the mean translational speed of the free particles (and the cell's L·|λ|) has
//    stayed below `rest_speed`·V₀ for `window` steps. A mean, not a maximum, and no spins: a
//    rattler may spin, or roll round its cage, for ever without losing energy.
// 3. Certificate, on a copy of the state (docs/method.md, "Until static"):
//    a. the admissible forces nearest to the last step's forces on the contacts whose gap is
//       at most `closure_gap` (indeterminacy/admissible_forces.hpp): forces that balance
//       every free particle (and the cell's pressure) to round-off inside the Coulomb cones.
//       If there are none and `refine_max_iterations` > 0, the last step's forces are
//       refined first by a static solve from rest started from them (at most that many
//       sweeps, fewer on a state that is not static: RefineStaticForces below), and the
//       nearest admissible forces to the refined ones are sought: in large
//       cells the capped steps leave the long-wavelength part of the forces unresolved, so
//       a static packing's last step forces can be too far from any admissible network.
//       The projection is local (a least-norm correction of the reference and at most 20
//       active-set rounds) and can miss a network far from the reference; with
//       `linear_program` the LP then decides whether any admissible network exists on these
//       contacts (exact, and slow: 20-100 s at N = 4000, so it is the last resort). The
//       contacts are detected up to `closure_gap`;
//    b. contact closure (contact_closure.hpp): the smallest displacement that brings the
//       gaps of the carrying (and of any overlapping) contacts to zero, typically 1e-6;
//    c. the same certificate again on the closed state, with only contacts closed to
//       `closed_gap_tolerance` counted as closed (the static solve's rule);
//    d. the static solve of the closed state started from those forces (the unjam residual,
//       docs/residual.md) must converge to `static_tolerance` with every particle balanced
//       within `equilibrium_tolerance` and P_in = P_ext within `pressure_tolerance`.
//    If admissible forces exist, one contact-dynamics step from rest moves nothing: the
//    packing is static and is returned at rest (velocities, spins and λ zero) with the
//    forces of the check in `final_check`. A failed attempt leaves the dynamics untouched,
//    and the next one waits `retry_fraction` × (steps so far), so that attempts add at most
//    a fixed fraction of the cost.
// V₀ is √(g R_max) under gravity and √(P_ext/ρ) under a pressure bath.
#pragma once

#include <functional>
#include <string>

#include "unjam/indeterminacy/admissible_forces.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/stepping/simulation.hpp"

namespace unjam {

struct RelaxOptions {
  double step_tolerance = 1e-4;   // per dynamics step
  int step_max_iterations = 500;  // sweeps per dynamics step
  double rest_speed = 1e-2;       // mean speed, × V₀
  int window = 20;                // steps
  double retry_fraction = 0.1;
  double closure_gap = 1e-6;           // contacts this close may carry force and be closed
  double closed_gap_tolerance = 1e-9;  // as the static solve
  int max_steps = 1000000;
  std::string static_backend = "nsgs";  // of the static check (the steps use the simulation's)
  double static_tolerance = 1e-10;
  SweepOrder sweep_order = SweepOrder::kRandom;  // of the static solves (NSGS)
  int threads = 1;  // of the static solves (NSGS, SolverOptions::nsgs.threads)
  int static_max_iterations = 100000;
  int refine_max_iterations = 0;  // 3a's refining static solve; 0 = none
  bool linear_program = false;    // 3a: if the projections fail, the LP decides (slow)
  double equilibrium_tolerance = 1e-8;
  double pressure_tolerance = 1e-8;
  // Called every `progress_interval` steps, 0 = never.
  int progress_interval = 0;
  std::function<void(const Simulation&, int step, const StepReport&)> progress;
  // Called after every certificate with the report so far.
  std::function<void(const struct RelaxReport&)> on_check;
  // Called every `checkpoint_interval` steps (0 = never) with the simulation and the report,
  // which is all the state of the run: the callback may save it, and may replace the
  // simulation's state by what it saved (so that a resumed run is bit for bit the same).
  int checkpoint_interval = 0;
  std::function<void(Simulation&, const struct RelaxReport&)> on_checkpoint;
};

struct RelaxReport {
  bool jammed = false;
  int steps = 0;
  int static_checks = 0;              // certificates attempted
  int unconverged_steps = 0;          // steps whose solve hit its iteration limit
  AdmissibleForces certificate;       // the last certificate
  std::string check_message;          // why the last attempt failed, if it did
  double closure_displacement = 0.0;  // largest displacement of the last contact closure
  StaticSolution final_check;         // static solve of the certified state (if any)
  int refined_checks = 0;             // certificates that refined the step's forces (3a)
  double pressure_mismatch = 0.0;     // |P_in/P_ext − 1| of the final check (pressure bath)
  // The loop's own state, so that a run can resume from a checkpoint.
  int calm_steps = 0;    // consecutive steps below the rest speed
  int next_attempt = 0;  // no certificate before this step
};

// Runs from `resume` (a fresh report to start, or one saved by on_checkpoint together with
// the simulation's state).
RelaxReport RelaxToStatic(Simulation& simulation, const RelaxOptions& options,
                          RelaxReport resume = {});

// V₀ of a scene (see above); 1 without gravity and pressure.
double VelocityScale(const Scene& scene);

// Step 3a's refinement: a static solve from rest of `state` (at rest), started from
// `reference`, of at most `refine_max_iterations` NSGS sweeps, run in chunks of
// kRefineChunk. A state that is not static has a particle that the load moves in a step
// from rest; the solve converges to that motion, so the fastest speed stays put from chunk
// to chunk, where a static state's falls with the residual. On the 1600-disk piles the
// failed certificates' states kept 0.027–2.7 √(gR) to within 2 % from one chunk to the
// next; the passing ones fell by a third or more per chunk, from 2e-2 at most (μ = 1) and
// 1.2e-3 (μ = 0.1). So the refinement stops after a chunk whose fastest particle moves
// faster than 10 × `rest_speed`·V₀ and at least 0.9 times as fast as after the chunk before
// (`still_moving`): the certificate fails as it would have, at a fifth of the cost. Other
// backends get the whole budget in one solve.
inline constexpr int kRefineChunk = 3000;
// A chunk's answer is solved exactly on its pattern only within this factor of the
// tolerance (StaticSolveOptions::polish_reach). Measured on `unjam pack --n 3000 --mu 0.5`:
// no polish of the 29 chunks before certification succeeded (NSGS residuals 7e-8 to 8e-4
// against 1e-10), each cost 1.3–5.7 s against about 0.2 s for the chunk's sweeps.
inline constexpr double kRefinePolishReach = 100.0;
struct Refinement {
  std::vector<ContactForce> forces;
  int sweeps = 0;
  bool still_moving = false;
};
Refinement RefineStaticForces(const Scene& state, const std::vector<ContactForce>& reference,
                              const RelaxOptions& options);

// The packing protocols' time step, in units of T₀ = R_max / V₀ (1 for the defaults:
// R_max = 1, density 1, P_ext = 1 or g = 1). Measured on 1600-disk piles and cells of
// N = 500 and 3000 (docs/performance.md, "Time step of the packing runs"): 3–4× fewer
// steps than at 5e-3 (piles) and 1.5–3× than at 1e-2 (cells), the same packings within
// their seed-to-seed scatter; at 0.03 with a fixed tolerance of 1e-4 a pile never passes
// its certificate (hence LooseStepTolerance), and larger steps do not shorten a cell's run.
inline constexpr double kPackingTimeStep = 0.02;

// The per-step tolerance of loose (NSGS) dynamics steps at time step `dt_over_t0` (Δt/T₀):
// 1e-4 up to kPackingTimeStep, then 1e-4 (kPackingTimeStep · T₀ / Δt)². The unjam residual
// is relative to the step's impulses, which grow like Δt, so a fixed tolerance lets the
// steps' velocity errors, and the gaps they leave (error × Δt), grow like Δt²: at Δt = 0.03
// with 1e-4 a settled pile keeps gaps of order the certificate's 1e-6 and is never proven
// static; with the tolerance tightened this way it is (docs/performance.md).
double LooseStepTolerance(double dt_over_t0);

}  // namespace unjam
