// Small contact problems with closed-form solutions, shared by the solver tests.
#pragma once

#include "test_scenes.hpp"
#include "unjam/problem/assembly.hpp"
#include "unjam/problem/contact_problem.hpp"

namespace unjam::testing {

// One free disk (m = 1/2, I = 1/4, arm 1/2) on a floor, pushed down with velocity
// (vt, −vn): W_nn = 2, W_tt = 3, so the exact impulse is known in closed form. Normal
// (0, −1), tangent (1, 0): the slip is u_t = −v_x, and r_t > 0 pushes the disk along −x.
inline ContactProblem OneContact(double vn, double vt, double mu) {
  ContactProblem p;
  p.dt = 1e-3;
  p.frictional = true;
  p.inv_mass = {2.0};
  p.inv_inertia = {4.0};
  p.free_velocity = {Vec2(vt, -vn)};
  p.free_spin = {0.0};
  ProblemContact c;
  c.body_i = 0;
  c.normal = Vec2(0.0, -1.0);  // from the disk to the floor
  c.arm_i = 0.5;
  c.mu = mu;
  p.contacts = {c};
  return p;
}

// The contact problem of Stack(k, 1/2, g = 1, μ) from rest, Δt = 1.
inline ContactProblem StackProblem(int k, double mu) {
  const Scene s = Stack(k, 0.5, 1.0, mu);
  AssemblyOptions o;
  o.dt = 1.0;
  return AssembleProblem(s, DetectContacts(s, 1e-6), o).problem;
}

}  // namespace unjam::testing
