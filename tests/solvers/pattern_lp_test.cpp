// The pattern LP (solvers/pattern_lp.hpp): from an exact answer of a frictional step whose
// solutions form a family, it finds the member with the same motion pattern nearest the
// static forces, which is itself an exact solution; from a candidate whose pattern no
// solution has, it finds nothing and says so.
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/perturbation.hpp"
#include "unjam/solvers/pattern_lp.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {
namespace {

// The step of the 6th top shift of the bundled small pile (particle 33 pushed down by ξ),
// quasi-static: a hyperstatic pile, whose answers form a family.
struct PileShift {
  PerturbationOptions options;
  PerturbationBase base;
  ContactProblem problem;
  SolverGuess guess;  // the static forces' impulses
};

PileShift SmallPileShift() {
  PileShift s;
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/gravity-n100-mu0.5.unjam");
  s.base = PreparePerturbations(scene, s.options);
  const std::vector<PerturbationTarget> top = TopTargets(s.base);
  EXPECT_EQ(top[5].i, 33);
  StaticProblem posed = PosePerturbationProblem(s.base, top[5], s.options);
  s.problem = std::move(posed.assembled.problem);
  s.guess = std::move(posed.guess);
  return s;
}

double L1Distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().sum();
}

TEST(PatternLp, TheNearestMemberOfAnExactAnswersPatternIsExactAndNearer) {
  const PileShift s = SmallPileShift();
  SolverOptions o;
  o.tolerance = 1e-13;
  o.lemke.velocity_scale = s.options.gap / s.options.dt;
  const SolveResult path = MakeSolver("lemke")->Solve(s.problem, o, s.guess);
  ASSERT_TRUE(path.report.converged()) << path.report.message;
  const PatternSolution nearest =
      SolveOnPattern(s.problem, path.impulses, s.guess.impulses, o.lemke.velocity_scale, 1.0);
  ASSERT_TRUE(nearest.found) << nearest.message;
  EXPECT_LT(ComputeResidual(s.problem, nearest.impulses).residual, 1e-13);
  // Another member: impulses that differ by O(1), not by the O(ξ) of the response, and
  // nearer the static forces than the path's answer. (By how much depends on which member
  // the path ends on, which round-off decides: above 1 with the reference BLAS, 0.70 with
  // OpenBLAS; a million ξ tells a member from the response.)
  EXPECT_GT((nearest.impulses - path.impulses).cwiseAbs().maxCoeff(), 1e6 * s.options.gap);
  EXPECT_LT(L1Distance(nearest.impulses, s.guess.impulses),
            L1Distance(path.impulses, s.guess.impulses));
  // With the same motion: every end velocity within 1 % of the response of the path's.
  const Eigen::VectorXd v_path = EndVelocity(s.problem, path.impulses);
  const Eigen::VectorXd v_nearest = EndVelocity(s.problem, nearest.impulses);
  EXPECT_LT((v_nearest - v_path).cwiseAbs().maxCoeff(), 1e-2 * o.lemke.velocity_scale);
  EXPECT_EQ(nearest.pattern.held, 0);
  EXPECT_GT(nearest.pattern.sliding, 0);
}

TEST(PatternLp, APatternNoSolutionHasIsReported) {
  const PileShift s = SmallPileShift();
  // Pulling impulses (the static ones reversed) read as every contact open: nothing holds
  // the pile up against gravity.
  const Eigen::VectorXd pulling = -s.guess.impulses;
  const PatternSolution r =
      SolveOnPattern(s.problem, pulling, s.guess.impulses, s.options.gap / s.options.dt, 1.0);
  EXPECT_FALSE(r.found);
  EXPECT_GT(r.pattern.open,
            0.9 * s.problem.NumContacts());  // all but contacts without a static force
  EXPECT_NE(r.message.find("static forces of the pattern: infeasible"), std::string::npos)
      << r.message;
}

TEST(PatternLp, BadInputIsRefused) {
  const PileShift s = SmallPileShift();
  const Eigen::VectorXd& r = s.guess.impulses;
  EXPECT_THROW(SolveOnPattern(s.problem, r.head(3), r, 1e-9, 1.0), std::invalid_argument);
  Eigen::VectorXd nan = r;
  nan[0] = std::nan("");
  EXPECT_THROW(SolveOnPattern(s.problem, r, nan, 1e-9, 1.0), std::invalid_argument);
  EXPECT_THROW(SolveOnPattern(s.problem, r, r, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(SolveOnPattern(s.problem, r, r, 1e-9, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace unjam
