// Which backend solves a perturbation's step, and with which options.
#include <string>

#include "perturbation_internal.hpp"

namespace unjam {

namespace {
bool LemkeOptionsGiven(const PerturbationOptions& o) { return o.solver.lemke.pivots_per_row > 0; }

bool FixedVolumeCell(const PerturbationOptions& options, const Scene& scene) {
  return scene.effects.pressure_bath.has_value() && options.cell == CellCondition::kFixedVolume;
}
}  // namespace

std::string PerturbationBackend(const PerturbationOptions& options, const Scene&) {
  if (options.backend != "auto") return options.backend;
  return LemkeOptionsGiven(options) ? "lemke" : "rate";
}

std::string StepBackend(const PerturbationOptions& options, const Scene& scene) {
  if (options.backend != "auto" && options.backend != "rate") return options.backend;
  // At fixed volume the stress level of rigid grains in a frozen cell is itself free (any
  // multiple of a self-stress balances), and Lemke's path from zero impulses ends on the
  // unloaded solution (F_crit ≈ 0, docs/perturbations.md); newton's proximal steps stay
  // nearest the static forces.
  if (!scene.effects.Frictional() || FixedVolumeCell(options, scene)) return "newton";
  return AutoLeavesLemkeForSize(options, scene) ? "newton" : "lemke";
}

bool AutoLeavesLemkeForSize(const PerturbationOptions& options, const Scene& scene) {
  const bool automatic =
      options.backend == "auto" || options.backend == "rate";  // "rate": auto, resolved
  if (!automatic || !scene.effects.Frictional() || FixedVolumeCell(options, scene)) return false;
  // An option only lemke reads says which backend the user means, whatever the size.
  if (LemkeOptionsGiven(options)) return false;
  // Lemke's paths lengthen faster than the packing grows, and its default budget (100 000
  // pivots) runs out: measured on `--sample 8 --seed 3` of packings made by the same recipe
  // (docs/perturbations.md, "Which backend `auto` picks"), lemke resolves 5 of 8 openings
  // at 1 287 contacts (newton 4, none of them quasi-static), none of 4 at 2 515 contacts
  // (6–8 minutes each) and none at 3 854 (12 minutes), where newton answers in 15–40 s.
  return ForceCarryingPairs(scene).size() > kLemkeAutoContacts;
}

std::string PerturbationFallback(const PerturbationOptions& options, const Scene& scene) {
  if (options.fallback == "none") return "";
  if (options.fallback != "auto")
    return options.fallback == PerturbationBackend(options, scene) ? "" : options.fallback;
  if (options.backend != "auto") return "";
  if (StepBackend(options, scene) == "lemke") return "ipopt";
  // Frictional steps that `auto` gives to newton have no fallback: at fixed volume lemke
  // ends on the unloaded solution, and on large packings its paths run out of pivots
  // after minutes, as ipopt's fixed point stalls (1e-3 on N = 3000 openings).
  if (scene.effects.Frictional()) return "";
  // Frictionless, at fixed pressure or without a bath: newton's proximal steps crawl along
  // a self-stress that the perturbation must unload (a disk lifted off a column: its
  // contact keeps the static force to within ξ), and lemke's path solves it exactly.
  return FixedVolumeCell(options, scene) ? "" : "lemke";
}

void ResolveBackends(PerturbationOptions& options, const Scene& scene) {
  const std::string fallback = PerturbationFallback(options, scene);
  options.fallback = fallback.empty() ? "none" : fallback;
  options.backend = PerturbationBackend(options, scene);
}

namespace perturbation_internal {

// The one step of a perturbation: a static solve of the perturbed scene.
StaticSolveOptions StepOptions(const PerturbationBase& base, const PerturbationOptions& options) {
  StaticSolveOptions solve;
  solve.dt = options.dt;
  solve.closed_gap_tolerance = options.closed_gap_tolerance;
  solve.margin = DetectionMargin(options);
  solve.backend = StepBackend(options, base.scene);
  solve.solver = options.solver;
  solve.solver.tolerance = SolverToleranceFor(options, base);
  solve.solver.lemke.velocity_scale = options.gap / options.dt;
  solve.solver.newton.warm_probe = true;  // the static forces are the warm start
  solve.nearest_member = options.nearest_member;
  return solve;
}

}  // namespace perturbation_internal
}  // namespace unjam
