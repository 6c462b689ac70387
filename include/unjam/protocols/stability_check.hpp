// The stability check of a hard case (problems/hard/README.md, docs/stability.md): one
// static solve per backend from zero impulses, judged by the unjam residual and Siconos'
// error, solved twice for the same bits; then, for a scene at rest, a number of
// Moreau–Jean steps with the same backend, watching the overlap and the energy. A backend
// may fail a case, but it must say so: the verdict tells an honest report from a silent
// failure (a claimed solution above the tolerance, NaN or Inf, other bits on a rerun,
// overlap growth or energy created at rest).
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "unjam/analysis/equilibrium.hpp"
#include "unjam/problem/delassus_problem.hpp"
#include "unjam/scene/scene.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

struct StabilityCase {
  std::string name;
  std::variant<Scene, DelassusProblem> problem;
};

struct StabilityOptions {
  std::vector<std::string> backends;
  SolverOptions solver;  // its tolerance is the one every solve must reach
  int steps = 100;       // Moreau–Jean steps of a scene at rest
  double dt = 1e-3;
  double max_step_seconds = 60.0;  // the steps of one (case, backend) stop after this long
  // Overlap growth and energy created at rest above these count as failures: overlap in
  // units of the largest radius, energy relative to Σ m |g| R + P_ext V.
  double overlap_tolerance = 1e-9;
  double energy_tolerance = 1e-9;
  // A converged static solve of a scene at rest whose forces miss equilibrium by more than
  // this (max net force on a grain / mean contact force) is a silent failure: the residual
  // claimed the tolerance, the forces are wrong (an ill-conditioned case).
  double equilibrium_tolerance = kStaticEquilibriumTolerance;
  // The static solve as `unjam solve` gives it: the backend's answer solved exactly on its
  // contact pattern where that helps (solvers/pattern_polish.hpp). Off: the backend's own
  // answer, to audit a backend as it is.
  bool polish = true;
};

enum class StabilityVerdict {
  kSolved,    // converged to the tolerance; finite, reproducible, stable at rest
  kReported,  // not solved, and the backend says so (its status is not "converged")
  kFailed,    // a silent failure: see StabilityRow::message
};
const char* ToString(StabilityVerdict verdict);

struct StabilityRow {
  std::string name, backend;
  int contacts = 0;            // detected (a scene's) or stored
  SolveReport report;          // the static solve (residual of its impulses)
  double siconos_error = 0.0;  // NaN where the problem has no Siconos form
  double equilibrium = 0.0;    // a scene's EquilibriumReport::residual; NaN for a .dat
  bool finite = true;
  bool reproducible = true;
  bool at_rest = false;         // a scene with no prescribed motion or gap: stepped
  int steps = 0;                // steps done (≤ options.steps: the time budget)
  bool steps_converged = true;  // every step's solve converged
  double max_overlap = 0.0;     // largest overlap seen over the steps, / largest radius
  double overlap_growth = 0.0;  // that minus the initial overlap
  double energy_change = 0.0;   // largest E(t) − E(0) over the steps, relative
  StabilityVerdict verdict = StabilityVerdict::kSolved;
  std::string message;  // why kFailed or kReported
};

// One row per backend, in options.backends order. Throws std::invalid_argument for an
// unknown backend or invalid solver options.
std::vector<StabilityRow> CheckStability(const StabilityCase& c, const StabilityOptions& options);

// The total energy of a scene (free particles' kinetic and potential energy in gravity,
// the pressure bath's P_ext V and the cell's kinetic energy) and its scale
// Σ m |g| R + P_ext V (1 where both vanish).
double SceneEnergy(const Scene& scene);
double SceneEnergyScale(const Scene& scene);

}  // namespace unjam
