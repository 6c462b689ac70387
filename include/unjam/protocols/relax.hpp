// Run contact dynamics until the packing is static, and prove it with a static solve.
//
// Dynamics runs with a loose per-step tolerance and a budget of sweeps per step while grains
// are in flight (contact dynamics in dense packings is not solved tightly at every step:
// the sweeps needed grow like (L/d)²). When the mean translational speed (and the cell's
// L·|λ|) has stayed below `rest_speed`·V₀ for `window` steps, the state is quenched:
// `polish_steps` times, all velocities (and λ) are set to zero and one step is solved to
// `polish_tolerance`. From rest, a step moves only what the load can move, and closes the
// gaps of the carrying contacts to round-off (position-level Signorini): an overdamped
// finish that removes the last creep left by inexact dynamics steps. Then a static check
// is made: the static solve of the quenched state (docs/method.md), started from the last
// step's forces. Up to `quench_rounds` quench-and-check rounds are tried.
// Neither spins nor single particles are part of the criterion: a rattler may spin, or roll
// round its cage, for ever without losing energy.
// The packing is static (jammed) when that solve
//   - converges to the residual `static_tolerance`,
//   - leaves every free particle in force and torque balance within
//     `equilibrium_tolerance` of the mean contact force (from rest with Δt = 1 this also
//     bounds every end-of-step speed), and
//   - under a pressure bath, has the virial pressure equal to P_ext within
//     `pressure_tolerance` (relative).
// Otherwise the per-step tolerance is tightened (÷10, down to `tight_step_tolerance`) and
// dynamics goes on. A jammed state is returned at rest (velocities, spins and λ zero). V₀ is the velocity scale √(g R_max) under gravity, √(P_ext/ρ) under a
// pressure bath.
#pragma once

#include <functional>

#include "unjam/protocols/static_solve.hpp"
#include "unjam/stepping/simulation.hpp"

namespace unjam {

struct RelaxOptions {
  double loose_step_tolerance = 1e-4;
  double tight_step_tolerance = 1e-8;
  int step_max_iterations = 500;        // sweeps per dynamics step
  double rest_speed = 1e-4;             // mean speed, × V₀
  int window = 20;                      // steps
  int polish_steps = 5;
  int quench_rounds = 4;
  double polish_tolerance = 1e-10;
  int polish_max_iterations = 200000;
  int max_steps = 1000000;
  double static_tolerance = 1e-10;
  int static_max_iterations = 100000;   // sweeps of a static check; grow it with the size
  double equilibrium_tolerance = 1e-8;
  double pressure_tolerance = 1e-8;
  // Called every `progress_interval` steps, 0 = never.
  int progress_interval = 0;
  std::function<void(const Simulation&, int step, const StepReport&)> progress;
  // Called after every static check with the report so far (final_check is that check).
  std::function<void(const struct RelaxReport&)> on_check;
};

struct RelaxReport {
  bool jammed = false;
  int steps = 0;
  int static_checks = 0;
  int unconverged_steps = 0;            // steps whose solve hit its iteration limit
  double step_tolerance = 0.0;          // the per-step tolerance at the end
  StaticSolution final_check;           // the last static check (valid if static_checks > 0)
  double pressure_mismatch = 0.0;       // |P_in/P_ext − 1| of the last check (pressure bath)
};

RelaxReport RelaxToStatic(Simulation& simulation, const RelaxOptions& options);

// V₀ of a scene (see above); 1 without gravity and pressure.
double VelocityScale(const Scene& scene);

}  // namespace unjam
