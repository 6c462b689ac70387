// The perturbation solve: the rigid limit of stiff contacts (solvers/rate_path.hpp), posed
// from a perturbation base and turned back into a solution of the perturbation's time step,
// whose residual is the evidence for it. Internal to src/protocols.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "unjam/problem/self_stress.hpp"
#include "unjam/protocols/perturbation.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/solvers/rate_path.hpp"

namespace unjam {

// The unperturbed step of a base in the rate problem's coordinates: computed once per
// base (a sparse QR of the Jacobian), shared by all its perturbations.
struct RateBase {
  StaticProblem posed;                   // the step from rest, contacts within the margin
  std::vector<int> closed;               // the problem contacts taken as closed, in problem order
  std::vector<int> closed_index;         // per problem contact: its index in `closed`, or −1
  Eigen::SparseMatrix<double> jacobian;  // H of the closed contacts
  Eigen::VectorXd impulses;              // their static impulses
  SelfStressBasis stresses;
  int UnknownsPerContact() const { return posed.assembled.problem.UnknownsPerContact(); }
};

RateBase PrepareRateBase(const PerturbationBase& base, const StaticSolveOptions& step);

// One perturbation's rate problem, and F_crit = critical_offset + critical · α.
struct RateTarget {
  RateProblem problem;
  Eigen::VectorXd critical;
  double critical_offset = 0.0;
  std::string refused;  // why the target has no rate problem (empty: it has one)
};

RateTarget PoseRateTarget(const RateBase& rb, const PerturbationTarget& target,
                          const PerturbationOptions& options);

// The solution of the perturbed step (`perturbed`, as PosePerturbationProblem poses it) on
// the path's contact states: the path's forces plus the impulses that accelerate the grains
// by ξ, and the motion, from one sparse linear system (UMFPACK), with the states that
// solution contradicts corrected (SolveOnPattern). The contacts open in the static state
// stay open unless `open_may_close`. Its report's residual is ComputeResidual's.
SolveResult StepOnPattern(const RateBase& rb, const RateTarget& rt, const RatePathResult& path,
                          const StaticProblem& perturbed, bool open_may_close);

}  // namespace unjam
