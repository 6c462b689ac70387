// Tests for src/solvers/de_saxce.cpp, ipopt_solver.cpp and nlopt_solver.cpp: what the
// convex backends add to the shared suite (backends_test.cpp): the convex relaxation as a
// different model, agreement with newton on unique forces, held (bilateral) contacts,
// warm starts, library status names, and the option rules.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <thread>

#include "solvers/de_saxce.hpp"
#include "test_problems.hpp"
#include "test_scenes.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/solvers/contact_solver.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {
namespace {

using testing::OneContact;
using testing::StackProblem;

const std::vector<std::string> kConvexBackends = {"ipopt", "nlopt"};

SolveResult SolveWith(const std::string& backend, const ContactProblem& p, SolverOptions o,
                      const SolverGuess& guess = {}) {
  return MakeSolver(backend)->Solve(p, o, guess);
}

SolverOptions Tolerance(double tolerance) {
  SolverOptions o;
  o.tolerance = tolerance;
  return o;
}

// The stack of StackProblem(k, μ) with contact h (between disks h − 1 and h) held at the
// relative normal velocity τ (positive: opening).
ContactProblem HeldStack(int k, int h, double tau) {
  ContactProblem p = StackProblem(k, 0.5);
  p.contacts[h].kind = ConstraintKind::kBilateral;
  p.contacts[h].target_velocity = tau;
  return p;
}

TEST(ConvexLaw, WithTheDeSaxceShiftItIsTheUnjamResidual) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> any(-1.0, 2.0);
  for (const ContactProblem& p : {StackProblem(6, 0.5), StackProblem(6, 0.0), HeldStack(6, 3, 0.1),
                                  OneContact(1.0, 3.0, 0.2)}) {
    const ConvexLaw law(p);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd r(p.NumUnknowns());
      for (Eigen::Index i = 0; i < r.size(); ++i) r[i] = any(rng);
      const Eigen::VectorXd u = PosedContactVelocity(p, r);
      const double expected = ComputeResidual(p, r).residual;
      EXPECT_NEAR(law.Residual(r, u, law.Shift(u)), expected, 1e-15 * std::max(1.0, expected));
    }
  }
  // At the exact sliding solution the law holds only with the shift μ|u_t| = 0.54.
  const ContactProblem slide = OneContact(1.0, 3.0, 0.2);
  const ConvexLaw law(slide);
  const Eigen::Vector2d r(0.5, 0.1);
  const Eigen::VectorXd u = PosedContactVelocity(slide, r);
  EXPECT_NEAR(law.Shift(u)[0], 0.2 * 2.7, 1e-15);
  EXPECT_LT(law.Residual(r, u, law.Shift(u)), 1e-15);
  EXPECT_GT(law.Residual(r, u, Eigen::Vector2d::Zero()), 0.1);
}

TEST(ConvexRelaxation, LetsASlidingContactSeparateWhereTheExactLawSlides) {
  // OneContact: W = diag(2, 3), free velocity (u_n, u_t) = (−1, −3), μ = 0.2. Without the
  // shift the minimiser lies on the cone edge r = a (1, μ) with a = (1 + 3μ) / (2 + 3μ²),
  // and the end normal velocity 2a − 1 > 0: the contact separates while it slides. The
  // exact law closes it: r = (1/2, μ/2), u_n = 0.
  const double mu = 0.2;
  const ContactProblem p = OneContact(1.0, 3.0, mu);
  const double a = (1.0 + 3.0 * mu) / (2.0 + 3.0 * mu * mu);
  for (const std::string& backend : kConvexBackends) {
    SolverOptions o = Tolerance(1e-12);
    o.de_saxce.convex_relaxation = true;
    const SolveResult relaxed = SolveWith(backend, p, o);
    EXPECT_EQ(relaxed.report.status, SolveStatus::kRelaxedModel)
        << backend << ": " << relaxed.report.message;
    EXPECT_NEAR(relaxed.impulses[0], a, 1e-10) << backend;
    EXPECT_NEAR(relaxed.impulses[1], mu * a, 1e-10) << backend;
    EXPECT_NEAR(PosedContactVelocity(p, relaxed.impulses)[0], 2.0 * a - 1.0, 1e-9) << backend;
    EXPECT_NEAR(relaxed.report.residual, ComputeResidual(p, relaxed.impulses).residual, 1e-15)
        << backend;
    EXPECT_GT(relaxed.report.residual, 0.1) << backend;  // honest against the exact law

    const SolveResult exact = SolveWith(backend, p, Tolerance(1e-12));
    ASSERT_TRUE(exact.report.converged()) << backend << ": " << exact.report.message;
    EXPECT_NEAR(exact.impulses[0], 0.5, 1e-11) << backend;
    EXPECT_NEAR(exact.impulses[1], 0.1, 1e-11) << backend;
    EXPECT_GT(exact.report.iterations, 1) << backend;  // the shift had to be found
  }
}

TEST(ConvexRelaxation, IsTheExactLawWhereNothingSlides) {
  for (const std::string& backend : kConvexBackends) {
    SolverOptions o = Tolerance(1e-12);
    o.de_saxce.convex_relaxation = true;
    const SolveResult stick = SolveWith(backend, OneContact(1.0, 0.3, 1.0), o);
    ASSERT_TRUE(stick.report.converged()) << backend << ": " << stick.report.message;
    EXPECT_NEAR(stick.impulses[0], 0.5, 1e-11) << backend;
    EXPECT_NEAR(stick.impulses[1], 0.1, 1e-11) << backend;
  }
}

TEST(ConvexBackends, HoldAContactOfAStackAtItsTargetVelocity) {
  // Stack of k = 6 disks (weight w = π/4, Δt = g = 1) with contact h = 3 held at the
  // opening rate τ: the lower block rests on the floor. τ = 0.1: the upper block rises as
  // one body, contact m ≥ h carries (k − m) w (1 + τ), contact m < h carries (h − m) w
  // plus contact h's force. τ = −1.5: disk h is pulled down faster than it falls, the held
  // contact is in tension, −w/2, the disks above fall freely (no force).
  const int k = 6, h = 3;
  const double w = std::numbers::pi / 4.0;
  for (double tau : {0.1, -1.5}) {
    const double held = tau > -1.0 ? (k - h) * w * (1.0 + tau) : w * (1.0 + tau);
    std::vector<double> expected(k);
    for (int m = 0; m < k; ++m) {
      if (m < h) expected[m] = (h - m) * w + held;
      else if (m == h) expected[m] = held;
      else expected[m] = tau > -1.0 ? (k - m) * w * (1.0 + tau) : 0.0;
    }
    for (const std::string& backend : kConvexBackends) {
      const SolveResult r = SolveWith(backend, HeldStack(k, h, tau), Tolerance(1e-12));
      ASSERT_TRUE(r.report.converged()) << backend << " tau " << tau << ": " << r.report.message;
      for (int m = 0; m < k; ++m) {
        EXPECT_NEAR(r.impulses[2 * m], expected[m], 1e-9)
            << backend << " tau " << tau << " contact " << m;
        EXPECT_NEAR(r.impulses[2 * m + 1], 0.0, 1e-9)
            << backend << " tau " << tau << " contact " << m;
      }
    }
  }
}

TEST(ConvexBackends, AgreeWithNewtonOnTheUniqueForcesOfAFrictionlessPacking) {
  // Isostatic, so the forces are unique; a pressure bath, so the cell rate couples every
  // contact. Measured largest differences to newton, all at residual 1e-13: 3.8e-12 of the
  // mean force (ipopt), 7.5e-11 (nlopt); 1e-9 leaves room for another machine.
  Scene scene = ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/pressure-n500-mu0.unjam");
  StaticSolveOptions o;
  o.solver.tolerance = 1e-13;
  o.backend = "newton";
  const StaticSolution reference = SolveStatic(scene, o);  // warm, from the stored forces
  ASSERT_TRUE(reference.report.converged()) << reference.report.message;
  scene.forces.clear();
  for (const std::string& backend : kConvexBackends) {
    o.backend = backend;
    const StaticSolution s = SolveStatic(scene, o);  // cold
    ASSERT_TRUE(s.report.converged()) << backend << ": " << s.report.message;
    ASSERT_EQ(s.forces.size(), reference.forces.size());
    double worst = 0.0;
    for (std::size_t k = 0; k < s.forces.size(); ++k) {
      worst = std::max(worst, std::abs(s.forces[k][0] - reference.forces[k][0]));
    }
    EXPECT_LT(worst, 1e-9 * reference.equilibrium.mean_contact_force) << backend;
  }
}

// Three hexagonal rows of 20 touching disks (radius 0.5) on a floor, periodic in x, μ = 0.5:
// hyperstatic, so self-stresses (Hᵀr = 0) leave the static forces undetermined and W
// singular along them.
Scene WideHexagonalPile() {
  Scene s;
  const int width = 20;
  s.cell.size = Vec2(width, 10.0);
  s.cell.periodicity = Periodicity::kX;
  s.cell.walls.push_back(testing::Floor());
  s.effects.gravity = Vec2(0.0, -1.0);
  s.effects.friction = 0.5;
  const double rise = std::sqrt(3.0) / 2.0;
  for (int row = 0; row < 3; ++row) {
    for (int k = 0; k < width; ++k) {
      const double x = std::fmod(0.5 * (row % 2) + 0.5 + k, width);
      s.particles.push_back(testing::Disk(x, 0.5 + row * rise, 0.5));
    }
  }
  return s;
}

TEST(Ipopt, DoesNotDriftAlongTheSelfStressesOfAHyperstaticPile) {
  // The interior point follows its central path to the analytic centre of the optimal face,
  // which lies at infinity along a self-stress: without the proximal term ipopt_solver.cpp
  // adds, this pile came back "converged" with a mean contact force of 8.9e4 against 0.62 for
  // newton (10⁵ times its weight per contact), its residual small only against that.
  const Scene scene = WideHexagonalPile();
  StaticSolveOptions o;
  o.solver.tolerance = 1e-12;
  o.backend = "newton";
  const StaticSolution reference = SolveStatic(scene, o);
  ASSERT_TRUE(reference.report.converged()) << reference.report.message;
  o.backend = "ipopt";
  const StaticSolution s = SolveStatic(scene, o);
  ASSERT_TRUE(s.report.converged()) << s.report.message;
  EXPECT_LT(s.equilibrium.mean_contact_force, 2.0 * reference.equilibrium.mean_contact_force);
}

TEST(ConvexBackends, EndOnTheirPatternSoThatAMassRatioOf1e6GetsItsAnalyticForces) {
  // A disk of density 1e6 on two light ones (problems/hard/README.md). The residual's
  // ρ = 1/W_nn is the light disks', so an answer just below the tolerance left the heavy
  // disk's contacts 1e-6 off; nlopt's steps at rest then created energy. Each
  // backend's own answer (no SolveStatic polish) must be the analytic one.
  const Scene scene = testing::HardCase("heavy-on-light");
  StaticSolveOptions o;
  const StaticProblem posed = PoseStaticProblem(scene, o);
  const ContactProblem& p = posed.assembled.problem;
  ASSERT_EQ(p.NumContacts(), 4);
  for (const std::string& backend : kConvexBackends) {
    SCOPED_TRACE(backend);
    const SolveResult r = SolveWith(backend, p, Tolerance(1e-10));
    ASSERT_TRUE(r.report.converged()) << r.report.message;
    for (int k = 0; k < 4; ++k) {
      const auto [fn, ft] =
          testing::HeavyOnLightForce(posed.contacts[posed.assembled.source_contact[k]].WithWall());
      EXPECT_NEAR(r.impulses[2 * k] / o.dt, fn, 1e-9 * fn) << k;
      EXPECT_NEAR(std::abs(r.impulses[2 * k + 1]) / o.dt, ft, 1e-9 * fn) << k;
    }
  }
}

TEST(ConvexBackends, AnExactWarmStartNeedsNoConvexSolve) {
  const ContactProblem p = StackProblem(12, 0.5);
  const SolverGuess exact{SolveWith("nsgs", p, Tolerance(1e-13)).impulses, {}};
  for (const std::string& backend : kConvexBackends) {
    const SolveResult r = SolveWith(backend, p, Tolerance(1e-12), exact);
    EXPECT_TRUE(r.report.converged()) << backend;
    EXPECT_EQ(r.report.iterations, 0) << backend;
  }
}

TEST(ConvexBackends, NameTheLibraryStatusWhenTheyStopShort) {
  SolverOptions o = Tolerance(1e-12);
  o.ipopt.max_iterations = 1;
  o.nlopt.max_evaluations = 1;
  for (auto [backend, status] :
       {std::pair{"ipopt", "Maximum_Iterations_Exceeded"}, std::pair{"nlopt", "MAXEVAL_REACHED"}}) {
    const SolveResult r = SolveWith(backend, StackProblem(12, 0.5), o);
    EXPECT_EQ(r.report.status, SolveStatus::kIterationLimit) << backend;
    EXPECT_NE(r.report.message.find(status), std::string::npos)
        << backend << ": " << r.report.message;
    EXPECT_NEAR(r.report.residual, ComputeResidual(StackProblem(12, 0.5), r.impulses).residual,
                1e-15);
  }
}

TEST(ConvexBackends, SolveFromParallelThreadsAsTheyDoAlone) {
  // perturb solves in parallel threads; MUMPS under Ipopt 3.11 is not thread-safe, so the
  // ipopt backend serialises its solves (ipopt_solver.cpp). Same answers, no crash.
  const ContactProblem p = StackProblem(12, 0.5);
  for (const std::string& backend : kConvexBackends) {
    const Eigen::VectorXd alone = SolveWith(backend, p, Tolerance(1e-12)).impulses;
    std::vector<Eigen::VectorXd> results(4);
    std::vector<std::thread> threads;
    for (std::size_t t = 0; t < results.size(); ++t) {
      threads.emplace_back(
          [&, t] { results[t] = SolveWith(backend, p, Tolerance(1e-12)).impulses; });
    }
    for (std::thread& t : threads) t.join();
    for (const Eigen::VectorXd& r : results) EXPECT_EQ(r, alone) << backend;
  }
}

TEST(Nlopt, CcsaqReachesTheStackForces) {
  // The stack's condition number is ~k² = 144, so a residual of 1e-10 bounds the force
  // errors by ~1e-8 of the mean force (about 5 weights here).
  SolverOptions o = Tolerance(1e-10);
  o.nlopt.algorithm = NloptAlgorithm::kCcsaq;
  const SolveResult r = SolveWith("nlopt", StackProblem(12, 0.5), o);
  ASSERT_TRUE(r.report.converged()) << r.report.message;
  for (int c = 0; c < 12; ++c)
    EXPECT_NEAR(r.impulses[2 * c], (12 - c) * std::numbers::pi / 4.0, 1e-7);
}

TEST(ConvexBackends, OptionRulesNameTheField) {
  SolverOptions o;
  o.ipopt.max_iterations = -1;
  EXPECT_THROW(Validate(o), std::invalid_argument);
  o = SolverOptions{};
  o.nlopt.max_evaluations = 0;
  try {
    Validate(o);
    ADD_FAILURE() << "nlopt.max_evaluations = 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nlopt.max_evaluations"), std::string::npos) << e.what();
  }
  for (NloptAlgorithm a : {NloptAlgorithm::kLbfgs, NloptAlgorithm::kCcsaq}) {
    EXPECT_EQ(NloptAlgorithmFromString(ToString(a)), a);
  }
  EXPECT_THROW(NloptAlgorithmFromString("bfgs"), std::invalid_argument);
  EXPECT_STREQ(ToString(SolveStatus::kRelaxedModel), "relaxed-model");
}

}  // namespace
}  // namespace unjam

namespace unjam {
namespace {

// Two contacts whose W is given: the symmetric matrix with eigenvalues `low` and `high`
// along (1, 0, 1, 0)/√2 and (1, 0, −1, 0)/√2, and 1 on the tangential diagonal.
DelassusProblem TwoContactsWithEigenvalues(double low, double high) {
  DelassusProblem p;
  const double a = 0.5 * (high + low), b = 0.5 * (high - low);
  Eigen::MatrixXd w = Eigen::MatrixXd::Identity(4, 4);
  w(0, 0) = w(2, 2) = a;
  w(0, 2) = w(2, 0) = -b;
  p.w = w.sparseView();
  // Contact 0 is pushed closed, contact 1 pulled open: with the singular W, r_0 − r_1 = 1
  // closes both exactly, for every r_1 ≥ 0 (indeterminate forces, as in a hyperstatic pile).
  p.q = Eigen::Vector4d(-1.0, 0.0, 1.0, 0.0);
  p.laws = {{0.5, ConstraintKind::kUnilateral}, {0.5, ConstraintKind::kUnilateral}};
  return p;
}

// A W with a negative eigenvalue makes the convex step non-convex: refused, with its reason;
// a positive semidefinite but singular W (the Delassus operator of a hyperstatic network)
// is not, and its solution is found.
TEST(ConvexBackends, RefuseAnIndefiniteWButNotASingularOne) {
  EXPECT_NE(IndefinitenessOf(TwoContactsWithEigenvalues(-1e-6, 2.0)), "");
  EXPECT_EQ(IndefinitenessOf(TwoContactsWithEigenvalues(0.0, 2.0)), "");
  EXPECT_EQ(IndefinitenessOf(TwoContactsWithEigenvalues(1.0, 2.0)), "");
  for (const std::string& backend : kConvexBackends) {
    SCOPED_TRACE(backend);
    SolverOptions o;
    o.tolerance = 1e-10;
    const SolveResult refused =
        MakeSolver(backend)->SolveDelassus(TwoContactsWithEigenvalues(-1e-6, 2.0), o);
    EXPECT_EQ(refused.report.status, SolveStatus::kUnsupported);
    EXPECT_NE(refused.report.message.find("not positive semidefinite"), std::string::npos);
    const DelassusProblem singular = TwoContactsWithEigenvalues(0.0, 2.0);
    const SolveResult solved = MakeSolver(backend)->SolveDelassus(singular, o);
    EXPECT_EQ(solved.report.status, SolveStatus::kConverged) << solved.report.message;
    EXPECT_LE(ComputeResidual(singular, solved.impulses).residual, o.tolerance);
  }
}

}  // namespace
}  // namespace unjam
