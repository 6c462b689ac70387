#include "unjam/protocols/static_solve.hpp"

#include "unjam/solvers/pattern_polish.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "unjam/problem/assembly.hpp"
#include "unjam/problem/kinematics.hpp"
#include "unjam/solvers/pattern_lp.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {
Scene AtRest(const Scene& scene) {
  Scene rest = scene;
  BringToRest(rest);
  return rest;
}

// Impulses Δt·f of the forces stored with the scene, matched to the problem's contacts by
// (i, j, image): a saved static state starts from its own solution.
Eigen::VectorXd StoredForcesGuess(const Scene& scene, const std::vector<Contact>& contacts,
                                  const AssembledProblem& assembled, double dt) {
  const ContactProblem& p = assembled.problem;
  Eigen::VectorXd guess = Eigen::VectorXd::Zero(p.NumUnknowns());
  if (scene.forces.empty()) return guess;
  const ForcesByContact stored(scene.forces);
  for (int k = 0; k < p.NumContacts(); ++k) {
    const ContactForce* it = stored.Find(contacts[assembled.source_contact[k]]);
    if (it == nullptr) continue;
    guess[k * p.UnknownsPerContact()] = dt * it->normal;
    if (p.frictional) guess[2 * k + 1] = dt * it->tangential;
  }
  return guess;
}
// The motion of every particle over the step: the solved bodies', and the known motion of
// prescribed ones (a shifted particle moves by its shift). Fixed particles stay; the
// largest speed is the bodies' own.
void RecordMotion(const Scene& scene, const AssembledProblem& assembled, const VelocityState& v,
                  double dt, StaticSolution& out) {
  const std::size_t n = assembled.body_of_particle.size();
  out.displacement.assign(n, Vec2::Zero());
  out.rotation.assign(n, 0.0);
  for (std::size_t b = 0; b < v.body.size(); ++b) {
    const int i = assembled.particle_of_body[b];
    out.displacement[i] = dt * v.body[b].head<2>();
    if (assembled.problem.frictional) out.rotation[i] = dt * v.body[b][2];
    out.max_speed = std::max(out.max_speed, v.body[b].head<2>().norm());
  }
  for (const PrescribedMotion& m : scene.effects.prescribed_motion) {
    out.displacement[m.particle] = dt * m.velocity;
    if (assembled.problem.frictional) out.rotation[m.particle] = dt * m.spin;
  }
  out.cell_strain = assembled.problem.cell ? dt * v.cell_rate : 0.0;
}

std::string FormatShort(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2g", x);
  return buffer;
}

// The nearest member of the answer's pattern family (StaticSolveOptions::nearest_member):
// replaces the answer where the pattern LP finds one that meets the tolerance. The pattern
// is read with κ = 1 (solvers/pattern_lp.hpp): an exact answer gives its own at any κ, and
// on inexact ones (newton's stalls) no κ tried (1e-2 to 1e4) gave a pattern with a solution.
void SelectNearestMember(const ContactProblem& p, const SolverGuess& guess,
                         const StaticSolveOptions& options, SolveResult& result) {
  double v_scale = options.solver.lemke.velocity_scale;
  if (!(v_scale > 0.0)) v_scale = std::max(VelocityOffset(p).cwiseAbs().maxCoeff(), 1e-300);
  const PatternSolution s = SolveOnPattern(p, result.impulses, guess.impulses, v_scale, 1.0);
  const double residual = s.found ? ComputeResidual(p, s.impulses).residual : 0.0;
  if (!s.found || !(residual <= options.solver.tolerance)) {
    result.report.message +=
        "; no member of its pattern meets the tolerance (" +
        (s.found ? "the pattern LP's: residual " + FormatShort(residual) : s.message) + ")";
    return;
  }
  result.impulses = s.impulses;
  result.basis.clear();  // not the path's basis: the small-gap check solves 10ξ as at ξ
  result.report.residual = residual;
  result.report.status = SolveStatus::kConverged;
  result.report.message +=
      "; nearest member of its pattern (pattern LP: " + std::to_string(s.pattern.open) + " open, " +
      std::to_string(s.pattern.sliding) + " sliding, " + std::to_string(s.pattern.sticking) +
      " sticking)";
  result.report.backend += "+pattern";
}
}  // namespace

StaticProblem PoseStaticProblem(const Scene& scene, const StaticSolveOptions& options) {
  const Scene rest = AtRest(scene);
  StaticProblem out;
  out.contacts = DetectContacts(rest, options.margin);
  EnsurePrescribedContacts(rest, out.contacts);
  AssemblyOptions assembly;
  assembly.dt = options.dt;
  assembly.closed_gap_tolerance = options.closed_gap_tolerance;
  out.assembled = AssembleProblem(rest, out.contacts, assembly);
  out.guess.impulses = StoredForcesGuess(scene, out.contacts, out.assembled, options.dt);
  return out;
}

StaticSolution SolveStatic(const Scene& scene, const StaticSolveOptions& options) {
  return SolveStatic(scene, PoseStaticProblem(scene, options), options);
}

StaticSolution SolveStatic(const Scene& scene, StaticProblem posed,
                           const StaticSolveOptions& options) {
  const ContactProblem& p = posed.assembled.problem;
  SolveResult result = MakeSolver(options.backend)->Solve(p, options.solver, posed.guess);
  if (result.report.residual <= options.polish_reach * options.solver.tolerance)
    result = PolishOnPattern(p, result, options.solver.tolerance);
  if (options.nearest_member) SelectNearestMember(p, posed.guess, options, result);
  return SolutionOf(scene, std::move(posed), result, options.dt);
}

StaticSolution SolutionOf(const Scene& scene, StaticProblem posed, const SolveResult& result,
                          double dt) {
  const Scene rest = AtRest(scene);
  StaticSolution out;
  out.contacts = std::move(posed.contacts);
  const AssembledProblem& assembled = posed.assembled;
  const ContactProblem& p = assembled.problem;
  out.report = result.report;
  if (!assembled.violated_immovable.empty()) {  // no solver can keep that contact closed
    out.report.status = SolveStatus::kNumericalFailure;
    const std::string solver =
        out.report.message.empty() ? "" : "; the solver: " + out.report.message;
    out.report.message =
        DescribeImmovableViolation(out.contacts[assembled.violated_immovable.front()]) + solver;
  }
  out.forces.assign(out.contacts.size(), Eigen::Vector2d::Zero());
  const int stride = p.UnknownsPerContact();
  for (int k = 0; k < p.NumContacts(); ++k) {
    out.forces[assembled.source_contact[k]] =
        Eigen::Vector2d(result.impulses[k * stride],
                        stride == 2 ? result.impulses[k * stride + 1] : 0.0) /
        dt;
  }
  if (!result.basis.empty()) {
    out.basis.assign(out.contacts.size(), 0);
    for (int k = 0; k < p.NumContacts(); ++k)
      out.basis[assembled.source_contact[k]] = result.basis[k];
  }
  RecordMotion(scene, assembled, EndVelocityState(p, result.impulses), dt, out);
  out.equilibrium = CheckEquilibrium(rest, out.contacts, out.forces);
  return out;
}

// Normals projected onto f_n >= 0: backends end a round-off outside the cone (newton by
// 1e-23, ipopt by its bound relaxation, -6e-13 on the 500-disk cell from cold), and a stored
// force never pulls: the reader refuses a negative one.
std::vector<ContactForce> ToContactForces(const StaticSolution& solution) {
  std::vector<ContactForce> forces;
  for (std::size_t k = 0; k < solution.contacts.size(); ++k) {
    const double normal = std::max(0.0, solution.forces[k][0]), tangential = solution.forces[k][1];
    if (normal == 0.0 && tangential == 0.0) continue;
    const Contact& c = solution.contacts[k];
    forces.push_back({c.i, c.j, c.image, normal, tangential});
  }
  return forces;
}

}  // namespace unjam
