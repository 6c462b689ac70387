#include "unjam/protocols/relax.hpp"

#include <algorithm>
#include <cmath>

namespace unjam {

double VelocityScale(const Scene& scene) {
  if (scene.effects.pressure_bath) return std::sqrt(scene.effects.pressure_bath->pressure);
  if (scene.effects.gravity) return std::sqrt(scene.effects.gravity->norm() * MaxRadius(scene));
  return 1.0;
}

namespace {

// Mean translational speed of the free particles, or the cell's L·|λ| if larger. A mean,
// not a maximum: a rattler can roll round its cage without losing energy for ever.
double MeanSpeed(const Scene& scene) {
  double sum = 0.0;
  int free = 0;
  for (const Particle& p : scene.particles) {
    if (p.fixed) continue;
    sum += p.velocity.norm();
    ++free;
  }
  double mean = free > 0 ? sum / free : 0.0;
  if (scene.effects.pressure_bath) {
    mean = std::max(mean, std::abs(scene.effects.pressure_bath->strain_rate) * scene.cell.size.maxCoeff());
  }
  return mean;
}

void SetStepSolve(Simulation& sim, double tolerance, int max_iterations) {
  sim.mutable_options().solver.tolerance = tolerance;
  sim.mutable_options().solver.max_iterations = max_iterations;
}

void BringToRest(Scene& scene) {
  for (Particle& p : scene.particles) {
    p.velocity = Vec2::Zero();
    p.spin = 0.0;
  }
  if (scene.effects.pressure_bath) scene.effects.pressure_bath->strain_rate = 0.0;
}

bool IsStatic(const Scene& scene, const RelaxOptions& o, RelaxReport& report) {
  StaticSolveOptions check;
  check.solver.tolerance = o.static_tolerance;
  check.solver.max_iterations = o.static_max_iterations;
  report.final_check = SolveStatic(scene, check);
  ++report.static_checks;
  const StaticSolution& s = report.final_check;
  bool ok = s.report.converged() && s.equilibrium.residual <= o.equilibrium_tolerance;
  if (scene.effects.pressure_bath) {
    report.pressure_mismatch = std::abs(s.equilibrium.pressure / scene.effects.pressure_bath->pressure - 1.0);
    ok = ok && report.pressure_mismatch <= o.pressure_tolerance;
  }
  return ok;
}

// Calm: close the carrying contacts exactly (quench steps from rest, solved tightly), then
// prove the state static, starting the static solve from its own forces. Up to
// `quench_rounds` rounds; true (and report.jammed) once a check passes.
bool QuenchAndProve(Simulation& sim, const RelaxOptions& o, RelaxReport& report) {
  SetStepSolve(sim, o.polish_tolerance, o.polish_max_iterations);
  for (int round = 0; round < o.quench_rounds && !report.jammed; ++round) {
    for (int k = 0; k < o.polish_steps; ++k, ++report.steps) {
      BringToRest(sim.mutable_scene());
      const StepReport quench = sim.Step();
      if (!quench.solve.converged()) ++report.unconverged_steps;
    }
    Scene state = sim.scene();
    state.forces = LastStepForces(sim);
    report.jammed = IsStatic(state, o, report);
    if (o.on_check) o.on_check(report);
  }
  return report.jammed;
}

}  // namespace

RelaxReport RelaxToStatic(Simulation& sim, const RelaxOptions& o) {
  RelaxReport report;
  report.step_tolerance = o.loose_step_tolerance;
  SetStepSolve(sim, report.step_tolerance, o.step_max_iterations);
  const double threshold = o.rest_speed * VelocityScale(sim.scene());
  int calm = 0;
  while (report.steps < o.max_steps) {
    const StepReport step = sim.Step();
    ++report.steps;
    if (!step.solve.converged()) ++report.unconverged_steps;
    calm = MeanSpeed(sim.scene()) < threshold ? calm + 1 : 0;
    if (o.progress && o.progress_interval > 0 && report.steps % o.progress_interval == 0) {
      o.progress(sim, report.steps, step);
    }
    if (calm < o.window) continue;
    if (QuenchAndProve(sim, o, report)) {
      BringToRest(sim.mutable_scene());
      break;
    }
    calm = 0;
    report.step_tolerance = std::max(o.tight_step_tolerance, report.step_tolerance * 0.1);
    SetStepSolve(sim, report.step_tolerance, o.step_max_iterations);
  }
  return report;
}

}  // namespace unjam
