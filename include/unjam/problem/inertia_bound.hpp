// How close to rest can a step from rest end? A linear program over the impulses alone,
// with no kinematics: the smallest possible largest inertial force, over every impulse
// the contact laws' cones admit,
//     t* = min_r max_d |p_d(r)| / (Δt s_d),   p = M v_free + Hᵀ r,
//     unilateral: r_n ≥ 0, |r_t| ≤ μ r_n;   bilateral: r_n free, r_t = 0,
// where p_d is the momentum that degree of freedom d gains in the step (m v, I ω, or the
// cell's M_λ D V λ) and s_d its force scale (a grain's: the mean contact force; a spin's:
// that force times the grain's radius; the cell's: D V P_ext, its virial at the bath's
// pressure). Every solution of the step's complementarity problem has impulses in those
// cones, so none can end with every inertial force below t* s_d: if t* exceeds the
// threshold of a quasi-static step, the step is dynamic, whatever a solver would make of
// it (docs/perturbations.md, "Dynamic before solving"). Complementarity and the
// non-penetration of the motion are not imposed, so t* is a lower bound, and t* = 0 says
// only that some network of forces balances every degree of freedom.
//
// Without a load (every free velocity zero) zero impulses already give t* = 0: no LP is
// solved. A frozen periodic cell (fixed volume) is such a step.
//
// The LP is posed in units of the scales (each row of p reads t* directly), so that CLP's
// tolerances (1e-9 here) are relative to the threshold's units: t* is known to about 1e-9.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "unjam/problem/contact_problem.hpp"

namespace unjam {

struct InertiaBound {
  double ratio = 0.0;   // t*: a lower bound of the step's largest inertial force over its scale
  bool decided = true;  // false: CLP stopped without an optimum (ratio then stays 0)
  std::string message;  // CLP's status when not decided
  int iterations = 0;   // simplex iterations
};

// Every free velocity zero (no gravity, no pressure bath, at rest): t* = 0, no LP needed.
bool IsUnloaded(const ContactProblem& problem);

// `force_scale`: s_d per degree of freedom (size NumDofs(), all positive).
InertiaBound SmallestInertia(const ContactProblem& problem, const Eigen::VectorXd& force_scale);

// The same LP for the contact openings of one static state, each of which differs from
// the unperturbed step only by the held contact's law (bilateral, frictionless). The
// unperturbed LP is solved once, with a spare free normal column per contact fixed at
// zero; an opening then only changes bounds (its contact's cone columns fixed at zero, its
// spare column released), and the dual simplex starts from the unperturbed optimal basis.
// On the default packing an opening the LP cannot decide then costs 16–26 pivots instead
// of about 2 000 (docs/performance.md, "Dynamic before solving"). Thread-safe: each call
// works on its own copy of the solved model.
class HeldContactInertia {
 public:
  // `unperturbed`: every contact unilateral. Solves its LP (CLP's dual simplex).
  HeldContactInertia(const ContactProblem& unperturbed, const Eigen::VectorXd& force_scale);
  ~HeldContactInertia();
  HeldContactInertia(const HeldContactInertia&) = delete;
  HeldContactInertia& operator=(const HeldContactInertia&) = delete;

  // SmallestInertia of the unperturbed problem with contact `contact` held.
  InertiaBound WithHeld(int contact) const;
  // Whether the unperturbed LP was solved (else WithHeld answers undecided).
  bool ready() const;

 private:
  struct Model;
  std::unique_ptr<Model> model_;
};

}  // namespace unjam
