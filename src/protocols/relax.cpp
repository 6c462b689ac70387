#include "unjam/protocols/relax.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "unjam/indeterminacy/equilibrium_system.hpp"
#include "unjam/protocols/contact_closure.hpp"

namespace unjam {

double VelocityScale(const Scene& scene) {
  if (scene.effects.pressure_bath) return std::sqrt(scene.effects.pressure_bath->pressure);
  if (scene.effects.gravity) return std::sqrt(scene.effects.gravity->norm() * MaxRadius(scene));
  return 1.0;
}

double LooseStepTolerance(double dt_over_t0) {
  const double ratio = kPackingTimeStep / dt_over_t0;
  return 1e-4 * std::min(1.0, ratio * ratio);
}

namespace {

// Mean translational speed of the free particles, or the cell's L·|λ| if larger.
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
    mean = std::max(
        mean, std::abs(scene.effects.pressure_bath->strain_rate) * scene.cell.size.maxCoeff());
  }
  return mean;
}

// The projection by default: the LP is slow at N ~ 1e3 (20-100 s at N = 4000), and a later
// attempt is cheaper. The LP (RelaxOptions::linear_program) is the last resort.
AdmissibleForces Admissible(const EquilibriumSystem& system,
                            const std::vector<ContactForce>& reference,
                            AdmissibleMethod method = AdmissibleMethod::kProjection) {
  AdmissibleOptions options;
  options.method = method;
  return NearestAdmissibleForces(system, StoredForcesOf(system, reference), options);
}

// `found` if the projection found forces; otherwise, when the options allow it, the LP's
// verdict. The projection is local (a least-norm correction of the reference, then at most
// 20 active-set rounds) and fails when the reference is far from every network; the LP
// decides whether one exists (N = 4000, mu = 1: docs/performance.md).
AdmissibleForces OrLinearProgram(AdmissibleForces found, const EquilibriumSystem& system,
                                 const std::vector<ContactForce>& reference,
                                 const RelaxOptions& o) {
  if (found.status == AdmissibleStatus::kAdmissible || !o.linear_program) return found;
  return Admissible(system, reference, AdmissibleMethod::kLinearProgram);
}

// The static solve of the certificate (3a's refinement, 3d's check), with a sweep limit.
StaticSolveOptions StaticOptions(const RelaxOptions& o, int max_iterations) {
  StaticSolveOptions solve;
  solve.closed_gap_tolerance = o.closed_gap_tolerance;
  solve.backend = o.static_backend;
  solve.solver.tolerance = o.static_tolerance;
  solve.solver.SetIterationLimit(max_iterations);
  solve.solver.nsgs.order = o.sweep_order;
  solve.solver.nsgs.threads = o.threads;
  return solve;
}

// Step 3b: close the carrying contacts, and any contact that overlaps (also one that the
// closure itself made overlap: up to three rounds).
bool CloseCarryingContacts(Scene& state, const EquilibriumSystem& system,
                           const Eigen::VectorXd& forces, double tolerance, RelaxReport& report) {
  std::vector<ContactKey> keys;
  for (std::size_t k = 0; k < system.contacts.size(); ++k) {
    const Contact& c = system.contacts[k];
    if (forces[system.UnknownsPerContact() * k] > 0.0 || c.gap < 0.0)
      keys.push_back({c.i, c.j, c.image});
  }
  for (int round = 0; round < 3; ++round) {
    const ClosureReport closure = CloseContacts(state, keys);
    report.closure_displacement = std::max(report.closure_displacement, closure.max_displacement);
    if (!closure.closed) return false;
    bool overlap = false;
    for (const Contact& c : DetectContacts(state, 0.0)) {
      if (c.gap >= -tolerance) continue;
      keys.push_back({c.i, c.j, c.image});
      overlap = true;
    }
    if (!overlap) return true;
  }
  return false;
}

// Step 3d: the static solve of the certified state.
bool StaticCheck(const Scene& state, const RelaxOptions& o, RelaxReport& report) {
  report.final_check = SolveStatic(state, StaticOptions(o, o.static_max_iterations));
  const StaticSolution& s = report.final_check;
  bool ok = s.report.converged() && s.equilibrium.residual <= o.equilibrium_tolerance;
  if (state.effects.pressure_bath) {
    report.pressure_mismatch =
        std::abs(s.equilibrium.pressure / state.effects.pressure_bath->pressure - 1.0);
    ok = ok && report.pressure_mismatch <= o.pressure_tolerance;
  }
  if (!ok) report.check_message = "the static solve of the certified state did not pass";
  return ok;
}

// Step 3 on `state` (a copy, at rest), starting from the last step's forces.
bool Certify(Scene& state, const std::vector<ContactForce>& reference, const RelaxOptions& o,
             RelaxReport& report) {
  report.check_message.clear();
  EquilibriumSystemOptions near;
  near.closed_gap_tolerance = o.closure_gap;
  near.margin = std::max(near.margin, o.closure_gap);
  const EquilibriumSystem loose = BuildEquilibriumSystem(state, near);
  report.certificate = Admissible(loose, reference);
  std::vector<ContactForce> refined;
  const std::vector<ContactForce>* best = &reference;  // the reference the LP starts from
  if (report.certificate.status != AdmissibleStatus::kAdmissible && o.refine_max_iterations > 0) {
    ++report.refined_checks;
    refined = RefineStaticForces(state, reference, o).forces;
    best = &refined;
    report.certificate = Admissible(loose, refined);
    if (report.certificate.status != AdmissibleStatus::kAdmissible)
      report.certificate.message += " (nor near the refined ones)";
  }
  report.certificate = OrLinearProgram(std::move(report.certificate), loose, *best, o);
  if (report.certificate.status != AdmissibleStatus::kAdmissible) {
    report.check_message = report.certificate.message;
    return false;
  }
  if (!CloseCarryingContacts(state, loose, report.certificate.forces, o.closed_gap_tolerance,
                             report)) {
    report.check_message = "contact closure failed";
    return false;
  }
  EquilibriumSystemOptions closed;
  closed.closed_gap_tolerance = o.closed_gap_tolerance;
  const EquilibriumSystem system = BuildEquilibriumSystem(state, closed);
  const std::vector<ContactForce> before_closure =
      ToContactForces(loose, report.certificate.forces);
  report.certificate =
      OrLinearProgram(Admissible(system, before_closure), system, before_closure, o);
  if (report.certificate.status != AdmissibleStatus::kAdmissible) {
    report.check_message = "after contact closure: " + report.certificate.message;
    return false;
  }
  state.forces = ToContactForces(system, report.certificate.forces);
  return StaticCheck(state, o, report);
}

}  // namespace

Refinement RefineStaticForces(const Scene& state, const std::vector<ContactForce>& reference,
                              const RelaxOptions& o) {
  Refinement out;
  Scene start = state;
  start.forces = reference;
  if (o.static_backend != "nsgs") {  // its iterations are not sweeps to share out
    const StaticSolution s = SolveStatic(start, StaticOptions(o, o.refine_max_iterations));
    out.sweeps = s.report.iterations;
    out.forces = ToContactForces(s);
    return out;
  }
  const double falling = 10.0 * o.rest_speed * VelocityScale(state);
  double previous = std::numeric_limits<double>::infinity();
  while (out.sweeps < o.refine_max_iterations) {
    const int chunk = std::min(kRefineChunk, o.refine_max_iterations - out.sweeps);
    StaticSolveOptions solve = StaticOptions(o, chunk);
    solve.polish_reach = kRefinePolishReach;
    const StaticSolution s = SolveStatic(start, solve);
    out.sweeps += s.report.iterations;
    start.forces = ToContactForces(s);
    // A converged step in which a grain still falls (an exact one: the polish on its
    // pattern, pattern_polish.hpp) shows the fall at once.
    if (s.report.converged() && s.max_speed > falling) {
      out.still_moving = true;
      break;
    }
    if (s.report.converged() || s.report.iterations < chunk) break;
    if (s.max_speed > falling && s.max_speed > 0.9 * previous) {
      out.still_moving = true;
      break;
    }
    previous = s.max_speed;
  }
  out.forces = std::move(start.forces);
  return out;
}

RelaxReport RelaxToStatic(Simulation& sim, const RelaxOptions& o, RelaxReport report) {
  sim.mutable_options().solver.tolerance = o.step_tolerance;
  sim.mutable_options().solver.SetIterationLimit(o.step_max_iterations);
  const double threshold = o.rest_speed * VelocityScale(sim.scene());
  while (report.steps < o.max_steps) {
    const StepReport step = sim.Step();
    ++report.steps;
    if (!step.solve.converged()) ++report.unconverged_steps;
    report.calm_steps = MeanSpeed(sim.scene()) < threshold ? report.calm_steps + 1 : 0;
    if (o.progress && o.progress_interval > 0 && report.steps % o.progress_interval == 0) {
      o.progress(sim, report.steps, step);
    }
    if (report.calm_steps >= o.window && report.steps >= report.next_attempt) {
      Scene state = sim.scene();
      BringToRest(state);
      ++report.static_checks;
      report.jammed = Certify(state, LastStepForces(sim), o, report);
      if (o.on_check) o.on_check(report);
      if (report.jammed) {
        sim.mutable_scene() = std::move(state);
        break;
      }
      report.next_attempt =
          report.steps + std::max(o.window, static_cast<int>(o.retry_fraction * report.steps));
    }
    if (o.on_checkpoint && o.checkpoint_interval > 0 && report.steps % o.checkpoint_interval == 0) {
      o.on_checkpoint(sim, report);
    }
  }
  return report;
}

}  // namespace unjam
