// The member of a step's family of solutions that a rule picks, among the solutions with
// a given motion pattern (docs/perturbations.md, "Which member: the pattern LP").
//
// A rigid frictional step may have a family of solutions: self-stresses of a hyperstatic
// packing can be added to the impulses as long as every contact keeps its law. Fix the
// pattern of the motion, per contact open (ũ_n > 0), sliding forward or backward
// (ũ_n = 0, ũ_t ≷ 0) or sticking (ũ = 0); then every law is linear:
//   open:     r = 0,                 ũ_n ≥ 0
//   sliding:  r_t = ∓μ r_n, r_n ≥ 0,  ũ_n = 0, ±ũ_t ≥ 0
//   sticking: |r_t| ≤ μ r_n,          ũ = 0
//   held (bilateral): r_t = 0, r_n free, ũ_n = 0
// and with the step's dynamics M v = M v_free + Hᵀ r the solutions with that pattern form
// a polyhedron. The pattern LP reads the pattern off a candidate answer (any backend's),
// and picks in the polyhedron the impulses nearest a reference in the L1 norm (for a
// perturbation: the static forces it starts from), by two COIN-OR CLP programs on their
// own scales, since a perturbation's response is ξ and its forces O(1):
//   1. the forces in the quasi-static limit: nearest the reference, balancing the load with
//      no motion, obeying the pattern's force laws;
//   2. the motion: the least change of those forces that gives them the pattern's
//      velocities, keeping the force laws.
// The result solves the step exactly, every law holding by construction, whatever the
// candidate's residual was. Where no solution has the candidate's pattern, or stage 2
// cannot reach the motion from stage 1's forces (a third of exact answers measured, for a
// reason not settled: docs/perturbations.md, "Which member"), it says so.
// The caller computes the residual (ComputeResidual): the pattern LP is no backend, whose
// entry point would.
#pragma once

#include <string>

#include <Eigen/Core>

#include "unjam/problem/contact_problem.hpp"

namespace unjam {

struct PatternCounts {
  int open = 0, sticking = 0, sliding = 0, held = 0;
};

struct PatternSolution {
  bool found = false;        // the LP is feasible and solved: `impulses` solve the step
  Eigen::VectorXd impulses;  // as ContactProblem lays them out
  PatternCounts pattern;
  long long iterations = 0;  // simplex iterations
  std::string message;
};

// `velocity_scale` V: the size of the motion (a perturbation: ξ/Δt). The pattern is read
// off the candidate by the natural map z = r / R − κ ũ / V of each law (R the mean normal
// impulse of the reference), κ = `velocity_weight`: open if z_n < 0, sliding if
// |z_t| > μ z_n, else sticking. An exact answer gives its own pattern at any κ > 0.
// `reference`: impulses to stay near, UnknownsPerContact() per contact. Throws
// std::invalid_argument for vectors of the wrong size or not finite, or a scale or
// weight that is not a finite positive number.
PatternSolution SolveOnPattern(const ContactProblem& problem, const Eigen::VectorXd& candidate,
                               const Eigen::VectorXd& reference, double velocity_scale,
                               double velocity_weight);

}  // namespace unjam
