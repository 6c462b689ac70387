// Lemke's complementary pivoting for a mixed linear complementarity problem, on sparse
// LU factorisations (UMFPACK) with product-form updates. The numerical core of the
// "lemke" backend (lemke.cpp), which poses the contact laws in this form.
//
// The problem: find free variables x (nf) and z ≥ 0, w ≥ 0 (n each) with
//     x − P z = x0                      (nf rows: the velocities, e.g. v = v_free + M⁻¹Hᵀr)
//     w = D x + E z + e,   wᵀz = 0     (n rows: the complementarity rows)
// Lemke's method adds an artificial z₀ ≥ 0 with covering vector 1 on the complementarity
// rows, starts from the basis (x, w) with z₀ as large as −min(e + D x0) and follows the
// path of complementary bases until z₀ leaves. The free variables never leave the basis.
//
// Why pivoting: the exact 2D Coulomb law is an LCP (its cone is polyhedral), and on a
// quasi-static perturbation of a hyperstatic packing the smooth methods stall on the
// combinatorics of which contacts stick, slide or open (docs/backends.md). A pivoting path
// settles that combinatorics exactly; each basis is solved to round-off.
//
// Degeneracy (many zero basic variables: contacts closed with zero force) is resolved by
// the lexicographic rule, i.e. the perturbation e + (ε, ε², …); it prevents cycling in
// exact arithmetic. In floating point, which rows tie is decided to a tolerance, and a
// wrong decision can end the path on a ray or make it cycle: the caller retries with
// another tolerance (lemke.cpp). A cycle is detected when a basis keeps coming back
// (a 64-bit hash of the set of basic variables, updated at every pivot), so that a cycling
// path stops soon instead of running to the pivot limit.
// Perturbed right-hand side (Mlcp::perturbation, small and generic, e.g. pseudo-random).
// The lexicographic rule is the limit ε → 0 of e + (ε, ε², …), and in floating point its
// ties must be told from round-off; a finite generic perturbation instead makes the
// problem non-degenerate outright, so that no two rows tie and the ratio test needs no
// tolerance to decide. The path is followed for e + perturbation; its final complementary
// basis is then solved again for e itself (the polish). Where the perturbation only broke
// ties, that basis is feasible for e to round-off and its solution is exact. Otherwise
// the polish leaves basic values below zero, by up to the perturbation times the
// amplification of the basis (10⁴–10⁵ on the μ = 0.1 packing); they are clamped, their
// largest is reported (LemkeResult::polish_violation), and the caller judges the answer
// by its residual.
//
// Termination on a ray (no blocking row) means the method found no solution: for a
// copositive-plus matrix that proves the problem infeasible (Cottle, Pang & Stone 1992,
// Thm 4.4.13), e.g. a prescribed motion that the rigid grains block.
#pragma once

#include <limits>

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace unjam::lemke_internal {

struct Mlcp {
  Eigen::SparseMatrix<double> p;         // nf × n
  Eigen::VectorXd x0;                    // nf
  Eigen::SparseMatrix<double> d;         // n × nf
  Eigen::SparseMatrix<double> e_matrix;  // n × n, the E above
  Eigen::VectorXd e;                     // n
  Eigen::VectorXd perturbation;  // n or empty: the path is followed for e + perturbation (below)
  // n or empty: a complementary basis (1: z_i basic, 0: w_i basic), e.g. the final basis
  // of a nearby problem's answer. If given, there is no path: that basis is solved for
  // this problem and its basic values clamped at zero (LemkeResult::polish_violation says
  // by how much); the caller judges the answer by its residual. The answer at 10ξ on the
  // basis of the answer at ξ has the same stick/slide/open pattern, and is linear in ξ
  // wherever that basis stays feasible.
  std::vector<char> given_basis;
  int NumFree() const { return static_cast<int>(x0.size()); }
  int NumComplementary() const { return static_cast<int>(e.size()); }
};

enum class LemkeOutcome { kSolved, kRay, kCycle, kPivotLimit, kSingularBasis };
const char* ToString(LemkeOutcome outcome);

struct LemkeResult {
  LemkeOutcome outcome = LemkeOutcome::kSingularBasis;
  Eigen::VectorXd x;  // free variables
  Eigen::VectorXd z;  // complementary variables
  int pivots = 0;
  int factorisations = 0;
  double polish_violation = 0.0;  // perturbed runs: −min of the basic values without the
                                  // perturbation, or 0 (given_basis: −min of that basis's values)
  std::vector<char> z_basic;  // solved: per complementary variable, 1 if z_i is in the final basis
  std::string message;
};

// `tie_tolerance`: basic values within tie_tolerance × the largest one block together in the
// ratio test (Harris), and are then ordered by the lexicographic rule.
// The path stops with kPivotLimit after max_pivots pivots or `time_limit` wall-clock
// seconds (its message says which).
LemkeResult SolveMlcp(const Mlcp& problem, int max_pivots, double tie_tolerance,
                      double time_limit = std::numeric_limits<double>::infinity());

}  // namespace unjam::lemke_internal
