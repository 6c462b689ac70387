// Tests for the Delassus (W-form) problem: src/problem/delassus_problem.cpp, the W-form
// residual and Siconos' error (src/solvers/residual.cpp), ContactSolver::SolveDelassus
// (solver_registry.cpp) and the W-form paths of nsgs (nsgs_delassus.cpp), newton, ipopt
// and nlopt (de_saxce.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>

#include "test_problems.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/problem/delassus_problem.hpp"
#include "unjam/problem/kinematics.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/solvers/contact_solver.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {
namespace {

using testing::OneContact;
using testing::StackProblem;

// A W-form problem from a dense W (row-major list), q and μ per contact.
DelassusProblem Dense(int nc, std::initializer_list<double> w, std::initializer_list<double> q,
                      std::initializer_list<double> mu) {
  DelassusProblem p;
  Eigen::MatrixXd dense(2 * nc, 2 * nc);
  auto it = w.begin();
  for (int i = 0; i < 2 * nc; ++i) {
    for (int j = 0; j < 2 * nc; ++j) dense(i, j) = *it++;
  }
  p.w = dense.sparseView();
  p.q = Eigen::Map<const Eigen::VectorXd>(q.begin(), 2 * nc);
  for (double m : mu) p.laws.push_back({m, ConstraintKind::kUnilateral});
  return p;
}

// W = diag(2, 4), q = (−1, d): r_n = 1/2 closes the contact; sticking needs r_t = −d/4.
DelassusProblem Diagonal(double qn, double d, double mu) {
  return Dense(1, {2, 0, 0, 4}, {qn, d}, {mu});
}

TEST(DelassusResidual, HandComputedValuesOfBothMeasures) {
  // r = 0 on W = diag(2, 4), q = (−1, 0.4), μ = 1: u = q, ŭ = (−0.6, 0.4).
  const DelassusProblem p = Diagonal(-1.0, 0.4, 1.0);
  const Eigen::Vector2d zero = Eigen::Vector2d::Zero();
  // unjam: ρ = 1/W_nn = 1/2, r − ρŭ = (0.3, −0.2) lies in the cone, e = ‖(0.3, −0.2)‖; no
  // impulse, so the scale is ρ|q_n| = 1/2.
  EXPECT_NEAR(ComputeResidual(p, zero).residual, std::sqrt(0.13) / 0.5, 1e-15);
  // Siconos: ρ = 1, r − ŭ = (0.6, −0.4) in the cone, e = ‖(0.6, −0.4)‖ / max(‖r‖, ‖u‖, ‖q‖).
  EXPECT_NEAR(SiconosError(p, zero), std::sqrt(0.52 / 1.16), 1e-15);
  // Both vanish at the sticking solution (1/2, −0.1).
  EXPECT_LT(ComputeResidual(p, Eigen::Vector2d(0.5, -0.1)).residual, 1e-15);
  EXPECT_LT(SiconosError(p, Eigen::Vector2d(0.5, -0.1)), 1e-15);
}

TEST(DelassusResidual, EqualsTheBodyFormResidualForTheSameImpulses) {
  // Any impulses, exact or not: the W form judges them as the body form does.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.3, 0.3);
  for (const ContactProblem& p :
       {OneContact(1.0, 0.3, 1.0), OneContact(1.0, 3.0, 0.2), StackProblem(6, 0.5)}) {
    const DelassusProblem w = ToDelassusProblem(p);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd r(p.NumUnknowns());
      for (Eigen::Index i = 0; i < r.size(); ++i) r[i] = 1.0 + noise(rng);
      const double body = ComputeResidual(p, r).residual;
      EXPECT_NEAR(ComputeResidual(w, r).residual, body, 1e-13 * std::max(1.0, body));
    }
  }
}

TEST(DelassusResidual, BundledPileStoredForcesJudgedAlikeInBothForms) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/gravity-n100-mu0.5.unjam");
  const StaticProblem posed = PoseStaticProblem(scene, StaticSolveOptions{});
  const ContactProblem& p = posed.assembled.problem;
  const DelassusProblem w = ToDelassusProblem(p);
  const Eigen::VectorXd& forces = posed.guess.impulses;
  ASSERT_EQ(forces.size(), p.NumUnknowns());
  // The stored (converged) forces, then the same forces spoiled by 1%.
  const double stored = ComputeResidual(p, forces).residual;
  EXPECT_NEAR(ComputeResidual(w, forces).residual, stored, 1e-12);
  const Eigen::VectorXd spoiled = 1.01 * forces;
  const double body = ComputeResidual(p, spoiled).residual;
  EXPECT_GT(body, 1e-4);
  EXPECT_NEAR(ComputeResidual(w, spoiled).residual, body, 1e-12 * body);
}

TEST(ToDelassus, FrictionlessProblemGetsObservingTangentRowsWithZeroFriction) {
  // Stack of 3 on a floor, frictionless: W_nn as the body form, W_tt = 1/m without spins.
  const ContactProblem p = StackProblem(3, 0.0);
  ASSERT_FALSE(p.frictional);
  const DelassusProblem w = ToDelassusProblem(p);
  ASSERT_EQ(w.NumContacts(), p.NumContacts());
  const double inv_mass = 1.0 / (std::numbers::pi * 0.25);
  for (int k = 0; k < w.NumContacts(); ++k) {
    EXPECT_EQ(w.laws[k].mu, 0.0);
    EXPECT_NEAR(w.w.coeff(2 * k, 2 * k), DelassusDiagonal(p, k)[0], 1e-15);
    EXPECT_NEAR(w.w.coeff(2 * k + 1, 2 * k + 1), k == 0 ? inv_mass : 2.0 * inv_mass, 1e-15);
  }
}

TEST(SolveDelassus, DefaultRefusesWithUnsupportedAndNamesTheBackend) {
  struct BodyOnly final : ContactSolver {
    std::string Name() const override { return "body-only"; }
    SolveResult DoSolve(const ContactProblem&, const SolverOptions&, const SolverGuess&) override {
      return {};
    }
  };
  const SolveResult r = BodyOnly().SolveDelassus(Diagonal(-1.0, 0.4, 1.0), SolverOptions{});
  EXPECT_EQ(r.report.status, SolveStatus::kUnsupported);
  EXPECT_NE(r.report.message.find("body-only"), std::string::npos) << r.report.message;
  EXPECT_EQ(r.impulses, Eigen::Vector2d::Zero());
  EXPECT_GT(r.report.residual, 0.5);
}

TEST(SolveDelassus, InconsistentSizesAreRejected) {
  DelassusProblem p = Diagonal(-1.0, 0.4, 1.0);
  p.q.resize(3);
  EXPECT_THROW(MakeSolver("nsgs")->SolveDelassus(p, SolverOptions{}), std::invalid_argument);
  p = Diagonal(-1.0, 0.4, -0.5);
  EXPECT_THROW(MakeSolver("newton")->SolveDelassus(p, SolverOptions{}), std::invalid_argument);
}

TEST(SolveDelassus, EveryBackendSolvesTheWForm) {
  for (const std::string& name : AvailableBackends()) {
    const SolveResult r =
        MakeSolver(name)->SolveDelassus(Diagonal(-1.0, 0.4, 1.0), SolverOptions{});
    EXPECT_EQ(r.report.status, SolveStatus::kConverged) << name << ": " << r.report.message;
  }
}

TEST(SolveDelassus, NsgsHonoursEverySweepOrderAndRelaxation) {
  // The frictionless stack has unique forces: contact c from the floor carries (k − c) weights.
  const int k = 12;
  const DelassusProblem p = ToDelassusProblem(StackProblem(k, 0.0));
  const double w = std::numbers::pi * 0.25;
  std::set<int> sweeps;  // each option changes the iteration, so the sweep counts differ
  for (SweepOrder order : {SweepOrder::kRandom, SweepOrder::kForward, SweepOrder::kSymmetric}) {
    for (double omega : {1.0, 1.5}) {
      SolverOptions o;
      o.nsgs.order = order;
      o.nsgs.relaxation = omega;
      o.tolerance = 1e-13;
      o.nsgs.check_interval = 1;
      const SolveResult r = MakeSolver("nsgs")->SolveDelassus(p, o);
      ASSERT_TRUE(r.report.converged()) << ToString(order) << " " << omega;
      EXPECT_NEAR(r.impulses[0], k * w, 1e-9) << ToString(order) << " " << omega;
      EXPECT_EQ(r.report.contact_updates, static_cast<std::int64_t>(r.report.iterations) * k);
      sweeps.insert(r.report.iterations);
    }
  }
  EXPECT_EQ(sweeps.size(), 6u);
}

TEST(SolveDelassus, ConvexBackendsRefuseANonSymmetricW) {
  // The De Saxcé fixed point minimises ½ rᵀ W r + (q + s)ᵀ r: a non-symmetric W has no such
  // objective. W = [[2, 1], [0, 4]] (the coupled block of CoupledBlockSticksAndSlidesExactly
  // with one off-diagonal entry dropped), which nsgs and newton solve as given.
  const DelassusProblem p = Dense(1, {2, 1, 0, 4}, {-1.0, 0.0}, {1.0});
  for (const char* name : {"ipopt", "nlopt"}) {
    const SolveResult r = MakeSolver(name)->SolveDelassus(p, SolverOptions{});
    EXPECT_EQ(r.report.status, SolveStatus::kUnsupported) << name;
    EXPECT_EQ(r.report.backend, name);
    EXPECT_NE(r.report.message.find("not symmetric"), std::string::npos) << r.report.message;
    EXPECT_EQ(r.impulses, Eigen::Vector2d::Zero()) << name;
    EXPECT_EQ(r.report.residual, ComputeResidual(p, r.impulses).residual) << name;
  }
  for (const char* name : {"nsgs", "newton"}) {
    EXPECT_EQ(MakeSolver(name)->SolveDelassus(p, SolverOptions{}).report.status,
              SolveStatus::kConverged)
        << name;
  }
  // Rounding-level asymmetry (an assembled W) is accepted.
  DelassusProblem q = Dense(1, {2, 1, 1 + 1e-14, 4}, {-1.0, 0.0}, {1.0});
  for (const char* name : {"ipopt", "nlopt"}) {
    const SolveResult r = MakeSolver(name)->SolveDelassus(q, SolverOptions{});
    EXPECT_EQ(r.report.status, SolveStatus::kConverged) << name << ": " << r.report.message;
  }
}

TEST(SolveDelassus, ConvexBackendsHoldMuZeroBilateralAndInertContacts) {
  // Three uncoupled contacts, W = diag(2, 4, 2, 4, 0, 0): μ = 0 (r_t = 0 exactly whatever
  // q_t), a held contact pulled apart (r_n = −1/2 < 0, r_t = 0), and a contact without
  // degrees of freedom (zero block: r = 0).
  DelassusProblem p = Dense(3, {2, 0, 0, 0, 0, 0, 0, 4, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0,
                                0, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
                            {-1.0, 3.0, 1.0, 0.5, -1.0, 1.0}, {0.0, 0.5, 0.5});
  p.laws[1].kind = ConstraintKind::kBilateral;
  for (const char* name : {"ipopt", "nlopt"}) {
    SolverOptions o;
    o.tolerance = 1e-13;
    const SolveResult r = MakeSolver(name)->SolveDelassus(p, o);
    ASSERT_TRUE(r.report.converged()) << name << ": " << r.report.message;
    EXPECT_NEAR(r.impulses[0], 0.5, 1e-12) << name;
    EXPECT_EQ(r.impulses[1], 0.0) << name;
    EXPECT_NEAR(r.impulses[2], -0.5, 1e-12) << name;
    EXPECT_EQ(r.impulses[3], 0.0) << name;
    EXPECT_EQ(r.impulses[4], 0.0) << name;
    EXPECT_EQ(r.impulses[5], 0.0) << name;
  }
}

class DelassusBackend : public ::testing::TestWithParam<std::string> {
 protected:
  // Every backend solves the W form (docs/backends.md): none may report kUnsupported.
  void SetUp() override {
    const SolveResult probe =
        MakeSolver(GetParam())->SolveDelassus(Diagonal(-1.0, 0.4, 1.0), SolverOptions{});
    ASSERT_NE(probe.report.status, SolveStatus::kUnsupported) << probe.report.message;
  }

  SolveResult Solve(const DelassusProblem& p, double tolerance) {
    SolverOptions o;
    o.tolerance = tolerance;
    return MakeSolver(GetParam())->SolveDelassus(p, o);
  }
};

TEST_P(DelassusBackend, SticksSlidesAndOpensOneContactExactly) {
  // W = diag(2, 4), q = (q_n, d): r_n = 1/2; stick r_t = −d/4; slide r_t = −μ/2 sign(u_t).
  for (auto [qn, d, mu, rn, rt] :
       {std::tuple{-1.0, 0.4, 1.0, 0.5, -0.1}, std::tuple{-1.0, 4.0, 0.3, 0.5, -0.15},
        std::tuple{-1.0, -4.0, 0.3, 0.5, 0.15}, std::tuple{1.0, 0.4, 1.0, 0.0, 0.0}}) {
    const SolveResult r = Solve(Diagonal(qn, d, mu), 1e-14);
    ASSERT_TRUE(r.report.converged()) << r.report.message;
    EXPECT_NEAR(r.impulses[0], rn, 1e-13) << "q_n " << qn << " d " << d;
    EXPECT_NEAR(r.impulses[1], rt, 1e-13) << "q_n " << qn << " d " << d;
  }
}

TEST_P(DelassusBackend, CoupledBlockSticksAndSlidesExactly) {
  // W = [[2, 1], [1, 4]], q = (−1, d). d = 0: stick, r = W⁻¹(1, 0) = (4, −1)/7.
  // d = 4, μ = 0.2: the sticking impulse (8, −9)/7 leaves the cone; sliding with u_t > 0,
  // r = r_n (1, −μ), u_n = 0: r_n (2 − μ) = 1, r = (5/9, −1/9), u_t = 4 + 1/9 > 0.
  for (auto [d, mu, rn, rt] :
       {std::tuple{0.0, 1.0, 4.0 / 7.0, -1.0 / 7.0}, std::tuple{4.0, 0.2, 5.0 / 9.0, -1.0 / 9.0}}) {
    const SolveResult r = Solve(Dense(1, {2, 1, 1, 4}, {-1.0, d}, {mu}), 1e-14);
    ASSERT_TRUE(r.report.converged()) << r.report.message;
    EXPECT_NEAR(r.impulses[0], rn, 1e-13) << "d " << d;
    EXPECT_NEAR(r.impulses[1], rt, 1e-13) << "d " << d;
  }
}

TEST_P(DelassusBackend, TwoCoupledContactsOneOpens) {
  // Normal block [[2, −1], [−1, 2]], q_n = (−1, 2): both closed would need r_1 < 0, so
  // contact 1 opens, r_0 = 1/2 and u_n,1 = −1/2 + 2 = 3/2 > 0. Tangents carry nothing.
  const DelassusProblem p = Dense(2, {2, 0, -1, 0, 0, 3, 0, 0, -1, 0, 2, 0, 0, 0, 0, 3},
                                  {-1.0, 0.0, 2.0, 0.0}, {0.5, 0.5});
  const SolveResult r = Solve(p, 1e-14);
  ASSERT_TRUE(r.report.converged()) << r.report.message;
  EXPECT_NEAR(r.impulses[0], 0.5, 1e-13);
  for (int i : {1, 2, 3}) EXPECT_NEAR(r.impulses[i], 0.0, 1e-13) << i;
}

TEST_P(DelassusBackend, FrictionlessStackGivesTheBodyFormForces) {
  // Contact c from the floor carries (k − c) weights; the exported tangent rows carry none.
  const int k = 12;
  const DelassusProblem p = ToDelassusProblem(StackProblem(k, 0.0));
  const SolveResult r = Solve(p, 1e-12);
  ASSERT_TRUE(r.report.converged()) << r.report.message;
  const double w = std::numbers::pi * 0.25;
  for (int c = 0; c < k; ++c) {
    EXPECT_NEAR(r.impulses[2 * c], (k - c) * w, 1e-9) << "contact " << c;
    EXPECT_EQ(r.impulses[2 * c + 1], 0.0) << "contact " << c;
  }
}

TEST_P(DelassusBackend, BundledFrictionalPileReachesTheBodyFormResidual) {
  // As Backend.FrictionalPileFromColdReachesTheSameResidualAsNsgs (backends_test), from cold
  // on the W form: nsgs and newton stall near 1e-7–1e-8 on the body form, ipopt does not.
  Scene scene = ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/gravity-n100-mu0.5.unjam");
  scene.forces.clear();
  const DelassusProblem p =
      ToDelassusProblem(PoseStaticProblem(scene, StaticSolveOptions{}).assembled.problem);
  if (GetParam() == "nlopt") {
    // The documented limit of nlopt (docs/backends.md), as in the body form: bounded L-BFGS
    // on the degenerate QP of the hyperstatic pile stalls near 1e-7 and says so.
    SolverOptions o;
    o.tolerance = 1e-7;
    o.nlopt.max_evaluations = 2000;
    const SolveResult r = MakeSolver(GetParam())->SolveDelassus(p, o);
    EXPECT_EQ(r.report.status, SolveStatus::kIterationLimit) << r.report.message;
    EXPECT_NE(r.report.message.find("MAXEVAL_REACHED"), std::string::npos) << r.report.message;
    EXPECT_LT(r.report.residual, 1e-6);
    EXPECT_EQ(r.report.residual, ComputeResidual(p, r.impulses).residual);
    return;
  }
  const SolveResult r = Solve(p, 1e-7);
  ASSERT_TRUE(r.report.converged()) << r.report.message << " residual " << r.report.residual;
  EXPECT_LE(ComputeResidual(p, r.impulses).residual, 1e-7);
}

TEST_P(DelassusBackend, ReportsAFailureInsteadOfHidingIt) {
  SolverOptions o;
  o.SetIterationLimit(1);
  o.newton.max_iterations = 1;
  o.ipopt.max_iterations = 1;
  o.nlopt.max_evaluations = 1;
  o.nsgs.check_interval = 1;
  o.tolerance = 1e-14;
  const SolveResult r =
      MakeSolver(GetParam())->SolveDelassus(ToDelassusProblem(StackProblem(40, 0.3)), o);
  EXPECT_EQ(r.report.status, SolveStatus::kIterationLimit);
  EXPECT_GT(r.report.residual, o.tolerance);
}

INSTANTIATE_TEST_SUITE_P(All, DelassusBackend, ::testing::ValuesIn(AvailableBackends()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace unjam
