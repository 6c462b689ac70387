// The static contact forces of a saved state: one contact-dynamics step from rest.
//
// Velocities (and the cell strain rate) are set to zero; the external load (gravity,
// pressure bath) acts for one step Δt; the impulses that keep every closed contact closed
// are the static forces times Δt. For a static packing the end-of-step velocities vanish
// and the forces do not depend on Δt. Gaps below `closed_gap_tolerance` count as closed.
// Forces stored with the scene are the initial guess (a saved static state starts from its
// own solution; with hyperstatic, path-dependent forces it stays on it).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "unjam/analysis/equilibrium.hpp"
#include "unjam/contacts/contact.hpp"
#include "unjam/problem/assembly.hpp"
#include "unjam/scene/scene.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

struct StaticSolveOptions {
  double dt = 1.0;
  double closed_gap_tolerance = 1e-9;  // length units
  double margin = 1e-6;                // contacts detected up to this gap
  std::string backend = "nsgs";
  SolverOptions solver;
  // After the backend: replace its answer by the solution with the same motion pattern
  // nearest the initial guess (the stored forces), by the pattern LP (solvers/pattern_lp.hpp),
  // where one exists and meets the tolerance. The rule that picks one member of a step's
  // family of solutions (docs/perturbations.md, "Which member").
  bool nearest_member = false;
  // The backend's answer is solved exactly on its contact pattern (PolishOnPattern) only
  // where its residual is within this factor of the tolerance: farther off, its pattern is
  // not the answer's, and the pattern solve, the costliest part of a static solve at
  // N ≥ 3 000, is wasted (RefineStaticForces' chunks).
  double polish_reach = std::numeric_limits<double>::infinity();
};

struct StaticSolution {
  std::vector<Contact> contacts;
  std::vector<Eigen::Vector2d> forces;  // (f_n, f_t) per contact
  // Per contact, the basis of a pivoting backend's answer (SolveResult::basis; 0 for a
  // contact outside the problem), or empty.
  std::vector<std::uint8_t> basis;
  SolveReport report;
  EquilibriumReport equilibrium;
  double max_speed = 0.0;  // largest end-of-step particle speed (0 if static)
  // End-of-step motion over the step, Δt·v and Δt·ω per particle (the known motion for
  // prescribed particles, zero for fixed ones), and the cell strain Δt·λ (0 without a
  // pressure bath).
  // For a static state all vanish; under a perturbation they are its response.
  std::vector<Vec2> displacement;
  std::vector<double> rotation;
  double cell_strain = 0.0;
};

StaticSolution SolveStatic(const Scene& scene, const StaticSolveOptions& options);

// The contact problem SolveStatic poses (and solves): the detected contacts and the
// assembled problem of one step from rest, and its guess, the stored forces' impulses. For
// exporting it (io/siconos_problem.hpp) or handing it to a backend directly.
struct StaticProblem {
  std::vector<Contact> contacts;
  AssembledProblem assembled;
  // impulses: Δt × the stored forces (zero for a contact without one); basis: empty, or
  // set by a caller that continues an earlier answer (a perturbation's small-gap check).
  SolverGuess guess;
};
StaticProblem PoseStaticProblem(const Scene& scene, const StaticSolveOptions& options);
// Solves a problem PoseStaticProblem(scene, options) has posed, for a caller that has
// looked at it first (a perturbation checks its kinematics), without posing it again.
StaticSolution SolveStatic(const Scene& scene, StaticProblem posed,
                           const StaticSolveOptions& options);

// The solution that `result` (impulses of posed's problem, from any backend or method) makes:
// forces per contact, the motion over the step, the equilibrium check.
StaticSolution SolutionOf(const Scene& scene, StaticProblem posed, const SolveResult& result,
                          double dt);

// The forces as the scene stores them (only force-carrying contacts), a normal force below
// zero (round-off of a backend) stored as 0.
std::vector<ContactForce> ToContactForces(const StaticSolution& solution);

}  // namespace unjam
