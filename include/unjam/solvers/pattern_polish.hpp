// A step solved exactly on a pattern of contact states. Where the states of an answer are
// known (which contacts stick, slide and open), the step is one sparse linear system: the
// grains' momentum balance with the impulse components those states leave free, and one
// velocity row per component they hold. Its solution obeys the contact law exactly if the
// pattern is right, and the states it contradicts show where the pattern is wrong.
//
// Two uses: the perturbation solve turns the rate path's end into the step's solution
// (protocols/perturbation_rate.hpp), and PolishOnPattern turns an iterative backend's
// answer, converged to the residual but only to cond(W) × residual in its forces
// (docs/residual.md), into an exact one where its pattern is right.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "unjam/problem/contact_problem.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

enum class ContactState : unsigned char { kStick, kSlidePositive, kSlideNegative, kOpen };

// The step with every contact in its state (one per problem contact), from `impulses`: the
// impulses the free components start from (a sticking contact's both, a sliding one's
// normal with the friction on the cone's edge, a bilateral one's normal); an open
// contact has none. The report's residual is ComputeResidual's; status kNumericalFailure
// if the system is singular.
SolveResult SolveOnStates(const ContactProblem& problem, const Eigen::VectorXd& impulses,
                          const std::vector<ContactState>& states);

// Of the contacts whose state the answer `solved` contradicts (a sticking contact pushed
// out of its cone, an open one closing, a sliding one turning back), gives those that break
// their law most (natural-map error at least half the largest among them) the state their
// motion asks for; contacts with frozen[k] set keep theirs. Returns whether any changed.
bool CorrectStates(const ContactProblem& problem, const SolveResult& solved,
                   const std::vector<char>& frozen, std::vector<ContactState>& states);

// SolveOnStates, then CorrectStates and again, up to `rounds` times, until an answer is at
// round-off (kRoundOffResidual), or after kPatternStallRounds rounds without a lower
// residual; returns the answer of lowest residual.
SolveResult SolveOnPattern(const ContactProblem& problem, const Eigen::VectorXd& impulses,
                           std::vector<ContactState> states, const std::vector<char>& frozen,
                           int rounds = 20);

// The states an approximate answer implies, as a semismooth Newton reads them: contact k
// closes where r_n − ρ ũ_n > 0, and sticks where |r_t − ρ u_t| ≤ μ (r_n − ρ ũ_n), ρ the
// residual's weight (residual.hpp).
std::vector<ContactState> StatesOf(const ContactProblem& problem, const Eigen::VectorXd& impulses);

// Residuals at or below this are round-off: such an answer is not polished.
inline constexpr double kRoundOffResidual = 1e-14;
// Corrections that have not lowered the residual in this many rounds have settled into a
// cycle of patterns (on N = 3000: three patterns in turn, one of them the best): no later
// round did better on any of the 478 pattern solves of the test suite, and stopping after
// 4 saves 40 % of their solves (docs/performance.md, "The pattern solve").
inline constexpr int kPatternStallRounds = 4;

// The answer `approximate` solved exactly on its own pattern (SolveOnPattern): where that
// lowers the residual of a converged answer, or brings a non-converged one to `tolerance`
// (then converged), the polished answer, its report saying so; else `approximate` as it is.
SolveResult PolishOnPattern(const ContactProblem& problem, const SolveResult& approximate,
                            double tolerance);

}  // namespace unjam
