// The step solved exactly on a pattern of contact states (solvers/pattern_polish.hpp):
// known answers where an iterative backend converges to the residual with wrong forces,
// or stops short of it; answers it must leave as they are.
#include "unjam/solvers/pattern_polish.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "../test_scenes.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {
namespace {

constexpr double kPi = 3.141592653589793;

using testing::HardCase;

// Two walls 1e-6 rad apart and a disk touching both (problems/hard/README.md): the floor
// (wall 0) carries the weight π/4, the tilted wall (wall 1) nothing. nsgs, newton and nlopt
// converge to 1e-12 with the weight on the tilted wall; their pattern, corrected, is exact.
TEST(PatternPolish, NearCoincidentContactsGetTheFloorsAnswer) {
  const Scene s = HardCase("near-coincident");
  for (const std::string backend : {"nsgs", "newton", "nlopt"}) {
    SCOPED_TRACE(backend);
    StaticSolveOptions o;
    o.backend = backend;
    const StaticSolution sol = SolveStatic(s, o);
    ASSERT_TRUE(sol.report.converged()) << sol.report.message;
    EXPECT_NE(sol.report.message.find("solved exactly on its contact pattern"), std::string::npos)
        << sol.report.message;
    ASSERT_EQ(sol.contacts.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      const bool floor = sol.contacts[k].j == -1;
      EXPECT_NEAR(sol.forces[k][0], floor ? kPi / 4.0 : 0.0, 1e-14);
      EXPECT_NEAR(sol.forces[k][1], 0.0, 1e-14);
    }
    EXPECT_LE(sol.equilibrium.residual, 1e-14);
  }
}

// A disk of density 1e6 on two light ones (problems/hard/README.md): newton converges to
// 8e-11 with the heavy disk's contacts 1e-4 low; polished, every force is the analytic one.
TEST(PatternPolish, HeavyOnLightGetsTheAnalyticForces) {
  const Scene s = HardCase("heavy-on-light");
  StaticSolveOptions o;
  o.backend = "newton";
  const StaticSolution sol = SolveStatic(s, o);
  ASSERT_TRUE(sol.report.converged()) << sol.report.message;
  ASSERT_EQ(sol.contacts.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    const auto [fn, ft] = testing::HeavyOnLightForce(sol.contacts[k].WithWall());
    EXPECT_NEAR(sol.forces[k][0], fn, 1e-9 * fn) << k;
    EXPECT_NEAR(std::abs(sol.forces[k][1]), ft, 1e-9 * fn) << k;
  }
}

// NSGS stopped after 3 sweeps on a stack of 4 disks: not converged, but its pattern (all
// stick) is right, so the polish brings it to the tolerance and to the analytic forces:
// the contact below disk i carries the weight of the disks from i up.
TEST(PatternPolish, BringsAnUnconvergedAnswerWithTheRightPatternToTheTolerance) {
  const Scene s = testing::Stack(4, 0.5, 1.0, 0.5);
  StaticSolveOptions o;
  o.solver.nsgs.max_sweeps = 3;
  o.solver.nsgs.check_interval = 1;
  const StaticProblem posed = PoseStaticProblem(s, o);
  const ContactProblem& p = posed.assembled.problem;
  const SolveResult raw = MakeSolver("nsgs")->Solve(p, o.solver);
  ASSERT_FALSE(raw.report.converged());
  const SolveResult polished = PolishOnPattern(p, raw, o.solver.tolerance);
  ASSERT_TRUE(polished.report.converged()) << polished.report.message;
  EXPECT_LE(polished.report.residual, 1e-14);
  EXPECT_EQ(polished.report.residual, ComputeResidual(p, polished.impulses).residual);
  const double weight = kPi * 0.25;
  const StaticSolution sol = SolutionOf(s, posed, polished, o.dt);
  for (std::size_t k = 0; k < sol.contacts.size(); ++k) {
    const Contact& c = sol.contacts[k];
    const int below = c.WithWall() ? 4 : 4 - std::max(c.i, c.j);
    EXPECT_NEAR(sol.forces[k][0], below * weight, 1e-12) << k;
    EXPECT_NEAR(sol.forces[k][1], 0.0, 1e-12) << k;
  }
}

// Answers at round-off and non-finite ones are returned as they are.
TEST(PatternPolish, LeavesWhatItCannotImproveAsItIs) {
  const Scene s = testing::Stack(2, 0.5, 1.0, 0.5);
  StaticSolveOptions o;
  const StaticProblem posed = PoseStaticProblem(s, o);
  const ContactProblem& p = posed.assembled.problem;

  const SolveResult exact = MakeSolver("lemke")->Solve(p, o.solver);
  ASSERT_LE(exact.report.residual, kRoundOffResidual);
  const SolveResult same = PolishOnPattern(p, exact, o.solver.tolerance);
  EXPECT_EQ(same.report.message, exact.report.message);
  EXPECT_TRUE(same.impulses == exact.impulses);

  SolveResult broken = exact;
  broken.impulses[0] = std::numeric_limits<double>::quiet_NaN();
  broken.report.residual = std::numeric_limits<double>::quiet_NaN();
  broken.report.status = SolveStatus::kNumericalFailure;
  const SolveResult kept = PolishOnPattern(p, broken, o.solver.tolerance);
  EXPECT_EQ(kept.report.status, SolveStatus::kNumericalFailure);
  EXPECT_TRUE(std::isnan(kept.impulses[0]));
}

// SolveOnStates itself: a disk on a floor held sticking carries its weight, its friction
// zero; held open it carries nothing and falls by g Δt.
TEST(PatternPolish, SolveOnStatesGivesTheStepOfAKnownPattern) {
  const Scene s = testing::Stack(1, 0.5, 2.0, 0.5);
  StaticSolveOptions o;
  const StaticProblem posed = PoseStaticProblem(s, o);
  const ContactProblem& p = posed.assembled.problem;
  ASSERT_EQ(p.NumContacts(), 1);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.NumUnknowns());
  const SolveResult stick = SolveOnStates(p, zero, {ContactState::kStick});
  EXPECT_NEAR(stick.impulses[0], 2.0 * kPi * 0.25, 1e-14);
  EXPECT_NEAR(stick.impulses[1], 0.0, 1e-14);
  EXPECT_LE(stick.report.residual, 1e-14);
  const SolveResult open = SolveOnStates(p, zero, {ContactState::kOpen});
  EXPECT_EQ(open.impulses[0], 0.0);
  EXPECT_GT(open.report.residual, 0.1);  // falling into the floor: no solution
  std::vector<ContactState> states = {ContactState::kOpen};
  EXPECT_TRUE(CorrectStates(p, open, {0}, states));
  EXPECT_EQ(states[0], ContactState::kStick);
}

}  // namespace
}  // namespace unjam
