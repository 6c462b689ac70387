#include "unjam/protocols/stability_check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "unjam/problem/contact_problem.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/protocols/stored_problem.hpp"
#include "unjam/solvers/pattern_polish.hpp"
#include "unjam/solvers/residual.hpp"
#include "unjam/stepping/simulation.hpp"

namespace unjam {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

bool AllFinite(const Eigen::VectorXd& v) { return v.size() == 0 || v.allFinite(); }

bool SameBits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         (a.size() == 0 || std::memcmp(a.data(), b.data(),
                                       sizeof(double) * static_cast<std::size_t>(a.size())) == 0);
}

struct Solved {
  Eigen::VectorXd impulses;
  SolveReport report;
  double siconos_error = kNaN;
  int contacts = 0;
  double equilibrium = kNaN;
  std::vector<ContactForce> forces;  // a scene's: the warm start of its steps at rest
};

// A scene's static step from zero impulses (as `unjam compare` poses it), with the report
// SolutionOf gives (a prescribed motion into a fixed body is not converged, named).
Solved SolveScene(const Scene& scene, const std::string& backend, const SolverOptions& solver,
                  bool polish) {
  StaticSolveOptions o;
  o.backend = backend;
  o.solver = solver;
  StaticProblem posed = PoseStaticProblem(scene, o);  // solved without its guess: from zero
  const ContactProblem& problem = posed.assembled.problem;
  // As `unjam solve` gives it: the backend's answer, solved exactly on its pattern where
  // that helps (pattern_polish.hpp).
  SolveResult result = MakeSolver(backend)->Solve(problem, solver);
  if (polish) result = PolishOnPattern(problem, result, solver.tolerance);
  Solved out;
  out.impulses = result.impulses;
  if (AllFinite(result.impulses)) {
    try {
      out.siconos_error = SiconosError(ToDelassusProblem(problem), result.impulses);
    } catch (const std::exception&) {
      out.siconos_error = kNaN;  // a problem Siconos' form cannot hold
    }
  }
  // SolutionOf takes the posed problem: everything read from it above comes first.
  const StaticSolution s = SolutionOf(scene, std::move(posed), result, o.dt);
  out.contacts = static_cast<int>(s.contacts.size());
  out.equilibrium = s.equilibrium.residual;
  out.report = s.report;
  out.forces = ToContactForces(s);
  return out;
}

Solved SolveStored(const DelassusProblem& problem, const std::string& backend,
                   const SolverOptions& solver) {
  const StoredSolution s = SolveStoredProblem(problem, backend, solver);
  Solved out;
  out.impulses = s.impulses;
  out.report = s.report;
  out.siconos_error = s.siconos_error;
  out.contacts = problem.NumContacts();
  return out;
}

Solved SolveCase(const StabilityCase& c, const std::string& backend, const StabilityOptions& o) {
  if (const Scene* scene = std::get_if<Scene>(&c.problem))
    return SolveScene(*scene, backend, o.solver, o.polish);
  return SolveStored(std::get<DelassusProblem>(c.problem), backend, o.solver);
}

bool AtRest(const Scene& s) {
  if (!s.effects.prescribed_motion.empty() || !s.effects.prescribed_gaps.empty()) return false;
  if (s.effects.pressure_bath && s.effects.pressure_bath->strain_rate != 0.0) return false;
  return std::all_of(s.particles.begin(), s.particles.end(), [](const Particle& p) {
    return p.fixed || (p.velocity.isZero() && p.spin == 0.0);
  });
}

// `note` after the row's message, "; "-separated.
void AppendNote(StabilityRow& row, const std::string& note) {
  row.message += (row.message.empty() ? "" : "; ") + note;
}

// The steps of a scene at rest with one backend: the largest overlap and energy change.
// The steps start from the backend's static forces (as impulses over one step), so that a
// solved resting case is at rest from the first step.
void StepAtRest(const Scene& scene, const std::string& backend,
                const std::vector<ContactForce>& forces, const StabilityOptions& o,
                StabilityRow& row) {
  StepOptions step;
  step.dt = o.dt;
  step.backend = backend;
  step.solver = o.solver;
  Simulation sim(scene, step);
  std::vector<ContactForce> impulses = forces;
  for (ContactForce& f : impulses) {
    f.normal *= o.dt;
    f.tangential *= o.dt;
  }
  sim.RestoreWarmStart(impulses);
  const double radius = std::max(MaxRadius(scene), 1e-300);
  const double overlap0 = MaxOverlap(scene) / radius;
  const double e0 = SceneEnergy(scene), scale = SceneEnergyScale(scene);
  row.max_overlap = overlap0;
  const auto start = Clock::now();
  for (int k = 0; k < o.steps; ++k) {
    // The budget bounds the step in progress too: a backend's solve stops at what is left.
    const double left = o.max_step_seconds - Seconds(start);
    if (!(left > 0.0)) {
      AppendNote(row, "the time budget ran out after step " + std::to_string(k));
      break;
    }
    sim.mutable_options().solver.time_limit = std::min(o.solver.time_limit, left);
    const StepReport r = sim.Step();
    if (!r.solve.converged() && Seconds(start) >= o.max_step_seconds) {
      AppendNote(row,
                 "the time budget ran out in step " + std::to_string(k + 1) + " (not counted)");
      break;
    }
    ++row.steps;
    row.max_overlap = std::max(row.max_overlap, MaxOverlap(sim.scene()) / radius);
    row.energy_change = std::max(row.energy_change, (SceneEnergy(sim.scene()) - e0) / scale);
    if (!r.solve.converged() && row.steps_converged) {
      row.steps_converged = false;
      row.message =
          "step " + std::to_string(k + 1) + " not converged (" + ToString(r.solve.status) + ")";
    }
  }
  row.overlap_growth = row.max_overlap - overlap0;
}

std::string Scientific(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2e", x);
  return text;
}

void Judge(const StabilityOptions& o, StabilityRow& row) {
  auto fail = [&](const std::string& why) {
    row.verdict = StabilityVerdict::kFailed;
    row.message = why + (row.message.empty() ? "" : "; " + row.message);
  };
  if (!row.finite) return fail("NaN or Inf in the impulses");
  if (!row.reproducible) return fail("other bits on a rerun");
  if (row.report.converged() && !(row.report.residual <= o.solver.tolerance)) {
    return fail("reported converged at residual " + Scientific(row.report.residual));
  }
  if (row.at_rest && row.report.converged() && row.equilibrium > o.equilibrium_tolerance) {
    return fail("converged, but the forces miss equilibrium by " + Scientific(row.equilibrium) +
                " of the mean contact force");
  }
  // Overlap grown or energy created while every step claimed convergence is silent; after a
  // step that said it did not converge, it is that step's reported failure.
  const char* drift = row.overlap_growth > o.overlap_tolerance ? "overlap grew at rest"
                      : row.energy_change > o.energy_tolerance ? "energy created at rest"
                                                               : nullptr;
  if (drift != nullptr && row.steps_converged) return fail(drift);
  if (!row.report.converged() || !row.steps_converged) {
    row.verdict = StabilityVerdict::kReported;
    if (!row.report.converged())  // the static solve's reason first, then the steps'
      row.message = row.report.message + (row.message.empty() ? "" : "; " + row.message);
    if (drift != nullptr) row.message += std::string("; then ") + drift;
  }
}

}  // namespace

const char* ToString(StabilityVerdict v) {
  switch (v) {
    case StabilityVerdict::kSolved: return "solved";
    case StabilityVerdict::kReported: return "reported";
    case StabilityVerdict::kFailed: return "FAILED";
  }
  return "?";
}

double SceneEnergy(const Scene& s) {
  const Vec2 g = s.effects.gravity.value_or(Vec2::Zero());
  double e = 0.0;
  for (const Particle& p : s.particles) {
    if (p.fixed) continue;
    e += 0.5 * p.Mass() * p.velocity.squaredNorm() + 0.5 * p.Inertia() * p.spin * p.spin -
         p.Mass() * g.dot(p.position);
  }
  if (s.effects.pressure_bath) {
    const double volume = s.cell.size.x() * s.cell.size.y();
    const double rate = s.effects.pressure_bath->strain_rate;
    e += s.effects.pressure_bath->pressure * volume + 0.5 * CellInertia(s) * rate * rate;
  }
  return e;
}

double SceneEnergyScale(const Scene& s) {
  const double g = s.effects.gravity ? s.effects.gravity->norm() : 0.0;
  double scale = 0.0;
  for (const Particle& p : s.particles) {
    if (!p.fixed) scale += p.Mass() * g * p.radius;
  }
  if (s.effects.pressure_bath)
    scale += s.effects.pressure_bath->pressure * s.cell.size.x() * s.cell.size.y();
  return scale > 0.0 ? scale : 1.0;
}

std::vector<StabilityRow> CheckStability(const StabilityCase& c, const StabilityOptions& o) {
  Validate(o.solver);
  std::vector<StabilityRow> rows;
  for (const std::string& backend : o.backends) {
    StabilityRow row;
    row.name = c.name;
    row.backend = backend;
    const Solved first = SolveCase(c, backend, o);
    const Solved again = SolveCase(c, backend, o);
    row.contacts = first.contacts;
    row.report = first.report;
    row.siconos_error = first.siconos_error;
    row.equilibrium = first.equilibrium;
    row.finite = AllFinite(first.impulses) && std::isfinite(first.report.residual);
    row.reproducible = SameBits(first.impulses, again.impulses);
    const Scene* scene = std::get_if<Scene>(&c.problem);
    row.at_rest = scene != nullptr && AtRest(*scene);
    if (row.at_rest && row.finite && o.steps > 0) StepAtRest(*scene, backend, first.forces, o, row);
    Judge(o, row);
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace unjam
