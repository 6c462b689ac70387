// Tests for src/solvers/nsgs.cpp, residual.cpp and solver_registry.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "test_problems.hpp"
#include "test_scenes.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/solvers/contact_solver.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {
namespace {

using testing::OneContact;
using testing::StackProblem;

TEST(Cone, ProjectionOfInsideEdgeAndPolarPoints) {
  const double mu = 0.5;
  EXPECT_EQ(ProjectOnCone({1.0, 0.3}, mu), Eigen::Vector2d(1.0, 0.3));
  EXPECT_EQ(ProjectOnCone({-1.0, 0.1}, mu), Eigen::Vector2d(0.0, 0.0));
  const Eigen::Vector2d edge = ProjectOnCone({1.0, 2.0}, mu);
  EXPECT_NEAR(edge[1], mu * edge[0], 1e-15);
  // The projection residual is orthogonal to the edge.
  EXPECT_NEAR((Eigen::Vector2d(1.0, 2.0) - edge).dot(Eigen::Vector2d(1.0, mu)), 0.0, 1e-15);
}

TEST(Cone, ProjectionWithoutFrictionIsTheNonNegativeNormalHalfLine) {
  // With μ = 0 the cone is the half-line r_t = 0, r_n ≥ 0; its polar is r_n ≤ 0.
  EXPECT_EQ(ProjectOnCone({-1.0, 0.0}, 0.0), Eigen::Vector2d(0.0, 0.0));
  EXPECT_EQ(ProjectOnCone({-1.0, 0.5}, 0.0), Eigen::Vector2d(0.0, 0.0));
  EXPECT_EQ(ProjectOnCone({2.0, 0.5}, 0.0), Eigen::Vector2d(2.0, 0.0));
  EXPECT_EQ(ProjectOnCone({2.0, 0.0}, 0.0), Eigen::Vector2d(2.0, 0.0));
}

TEST(Residual, ZeroExactlyAtTheClosedFormSolutions) {
  // Sticking: W_nn = 2, W_tt = 2 + 0.25·4 = 3. Normal (0,−1), tangent (1, 0): the slip
  // u_t = −v_x, and r_t > 0 pushes the floor along +x, the disk along −x.
  ContactProblem stick = OneContact(1.0, 0.3, 1.0);
  EXPECT_LT(ComputeResidual(stick, Eigen::Vector2d(0.5, 0.1)).residual, 1e-15);
  EXPECT_GT(ComputeResidual(stick, Eigen::Vector2d(0.5, 0.0)).residual, 0.01);
  // Sliding: the tangential impulse is capped at μ r_n, opposing the slip.
  ContactProblem slide = OneContact(1.0, 3.0, 0.2);
  EXPECT_LT(ComputeResidual(slide, Eigen::Vector2d(0.5, 0.1)).residual, 1e-15);
  EXPECT_GT(ComputeResidual(slide, Eigen::Vector2d(0.5, 0.09)).residual, 0.01);
  // Separating: no impulse.
  ContactProblem open = OneContact(-1.0, 0.3, 1.0);
  EXPECT_EQ(ComputeResidual(open, Eigen::Vector2d(0.0, 0.0)).residual, 0.0);
  EXPECT_GT(ComputeResidual(open, Eigen::Vector2d(0.1, 0.0)).residual, 0.5);
}

TEST(Nsgs, SolvesOneContactExactlyInOneSweep) {
  for (auto [vn, vt, mu, rn, rt] :
       {std::tuple{1.0, 0.3, 1.0, 0.5, 0.1}, std::tuple{1.0, 3.0, 0.2, 0.5, 0.1},
        std::tuple{-1.0, 0.3, 1.0, 0.0, 0.0}}) {
    SolveResult r = MakeSolver("nsgs")->Solve(OneContact(vn, vt, mu), SolverOptions{});
    EXPECT_TRUE(r.report.converged());
    EXPECT_NEAR(r.impulses[0], rn, 1e-15);
    EXPECT_NEAR(r.impulses[1], rt, 1e-15);
    EXPECT_LE(r.report.iterations, 10);
  }
}

TEST(Nsgs, ReportsTheIterationLimitInsteadOfHidingIt) {
  SolverOptions o;
  o.nsgs.max_sweeps = 3;
  o.nsgs.check_interval = 1;
  SolveResult r = MakeSolver("nsgs")->Solve(StackProblem(30, 0.0), o);
  EXPECT_EQ(r.report.status, SolveStatus::kIterationLimit);
  EXPECT_EQ(r.report.iterations, 3);
  EXPECT_GT(r.report.residual, o.tolerance);
  EXPECT_FALSE(r.report.message.empty());
}

TEST(Nsgs, EverySweepOrderAndRelaxationReachesTheUniqueForces) {
  const ContactProblem p = StackProblem(12, 0.0);
  for (SweepOrder order : {SweepOrder::kRandom, SweepOrder::kForward, SweepOrder::kSymmetric,
                           SweepOrder::kLocal, SweepOrder::kHeight}) {
    for (double omega : {1.0, 1.5}) {
      SolverOptions o;
      o.nsgs.order = order;
      o.nsgs.relaxation = omega;
      o.tolerance = 1e-13;
      SolveResult r = MakeSolver("nsgs")->Solve(p, o);
      ASSERT_TRUE(r.report.converged()) << ToString(order) << " " << omega;
      // Contacts sorted by (i, j): the floor contact of disk 0 comes first (walls have j < 0).
      const double w = std::numbers::pi * 0.25;
      EXPECT_NEAR(r.impulses[0], 12 * w, 1e-9) << ToString(order) << " " << omega;
    }
  }
}

// A warm start from the solution needs no sweep, in the random order and in the local one
// (whose own layout of contacts and bodies must take the guess in and give it back intact).
TEST(Nsgs, WarmStartFromTheSolutionNeedsNoSweep) {
  const ContactProblem p = StackProblem(10, 0.3);
  SolverOptions o;
  o.tolerance = 1e-12;
  SolveResult cold = MakeSolver("nsgs")->Solve(p, o);
  ASSERT_TRUE(cold.report.converged());
  const SolverGuess guess{cold.impulses, {}};
  for (SweepOrder order : {SweepOrder::kRandom, SweepOrder::kLocal}) {
    o.nsgs.order = order;
    SolveResult warm = MakeSolver("nsgs")->Solve(p, o, guess);
    EXPECT_TRUE(warm.report.converged()) << ToString(order);
    EXPECT_EQ(warm.report.iterations, 0) << ToString(order);
    EXPECT_EQ(warm.impulses, cold.impulses) << ToString(order);
  }
}

// The local order keeps contacts and bodies in its own layout (Cuthill–McKee): every
// impulse must come back to its own contact. A stack of 200 disks has 200 contacts, four
// blocks, and unique forces: contact c from the floor carries (k − c) weights.
TEST(Nsgs, LocalOrderReturnsEveryImpulseToItsOwnContact) {
  const int k = 200;
  SolverOptions o;
  o.nsgs.order = SweepOrder::kLocal;
  o.tolerance = 1e-12;
  o.nsgs.max_sweeps = 1000000;
  const SolveResult r = MakeSolver("nsgs")->Solve(StackProblem(k, 0.3), o);
  ASSERT_TRUE(r.report.converged()) << r.report.residual;
  const double w = std::numbers::pi * 0.25;
  for (int c = 0; c < k; ++c) {
    EXPECT_NEAR(r.impulses[2 * c], (k - c) * w, 1e-6 * k * w) << "contact " << c;
    EXPECT_NEAR(r.impulses[2 * c + 1], 0.0, 1e-6 * k * w) << "contact " << c;
  }
}

// The height order lays the contacts out by ProblemContact::height: in a stack numbered
// from the top, the contact order of the problem (by particle index) is the reverse of the
// height order, and every impulse must still come back to its own contact. Contact c from
// the floor carries (k − c) weights, and its height is 2 r c.
TEST(Nsgs, HeightOrderReturnsEveryImpulseToItsOwnContact) {
  const int k = 40;
  const double r = 0.5;
  Scene s = testing::Stack(k, r, 1.0, 0.3);
  std::reverse(s.particles.begin(), s.particles.end());
  AssemblyOptions a;
  a.dt = 1.0;
  const ContactProblem p = AssembleProblem(s, DetectContacts(s, 1e-6), a).problem;
  ASSERT_EQ(p.NumContacts(), k);
  ASSERT_GT(p.contacts.front().height, p.contacts.back().height);  // problem order: top first
  SolverOptions o;
  o.nsgs.order = SweepOrder::kHeight;
  o.tolerance = 1e-12;
  o.nsgs.max_sweeps = 1000000;
  const SolveResult res = MakeSolver("nsgs")->Solve(p, o);
  ASSERT_TRUE(res.report.converged()) << res.report.residual;
  const double w = std::numbers::pi * r * r;
  for (int q = 0; q < k; ++q) {
    const int c = static_cast<int>(std::lround(p.contacts[q].height / (2.0 * r)));
    EXPECT_NEAR(res.impulses[2 * q], (k - c) * w, 1e-9 * k * w)
        << "contact " << q << " at level " << c;
    EXPECT_NEAR(res.impulses[2 * q + 1], 0.0, 1e-9 * k * w) << "contact " << q;
  }
}

TEST(Nsgs, SameSeedSameBits) {
  const ContactProblem p = StackProblem(15, 0.5);
  SolverOptions o;
  o.nsgs.seed = 42;
  const SolveResult a = MakeSolver("nsgs")->Solve(p, o);
  const SolveResult b = MakeSolver("nsgs")->Solve(p, o);
  EXPECT_EQ(a.impulses, b.impulses);
}

// Threads (nsgs_domains.hpp) split the bodies into domains along the contact graph. Here
// 55 stacks of 20 disks (1 100 contacts, more than kParallelContacts), whose forces are
// unique: contact c from the floor carries (20 − c) weights. Every order must return them
// on two threads, each impulse to its own contact.
ContactProblem Stacks(int columns, int k, double mu) {
  Scene s = testing::Stack(k, 0.5, 1.0, mu);
  s.cell.size.x() = 1.5 * columns;
  s.particles.clear();
  for (int col = 0; col < columns; ++col) {
    for (int i = 0; i < k; ++i) s.particles.push_back(testing::Disk(1.5 * col, 0.5 + i, 0.5));
  }
  AssemblyOptions a;
  a.dt = 1.0;
  return AssembleProblem(s, DetectContacts(s, 1e-6), a).problem;
}

TEST(NsgsThreads, ReachTheUniqueForcesOfStacks) {
  const int columns = 55, k = 20;
  const ContactProblem p = Stacks(columns, k, 0.3);
  ASSERT_EQ(p.NumContacts(), columns * k);
  const double w = std::numbers::pi * 0.25;
  for (SweepOrder order : {SweepOrder::kHeight, SweepOrder::kRandom, SweepOrder::kLocal}) {
    SolverOptions o;
    o.nsgs.threads = 2;
    o.nsgs.order = order;
    o.tolerance = 1e-12;
    o.nsgs.max_sweeps = 1000000;
    const SolveResult r = MakeSolver("nsgs")->Solve(p, o);
    ASSERT_TRUE(r.report.converged()) << ToString(order) << " " << r.report.residual;
    for (int q = 0; q < p.NumContacts(); ++q) {
      const int c = static_cast<int>(std::lround(p.contacts[q].height));
      EXPECT_NEAR(r.impulses[2 * q], (k - c) * w, 1e-9 * k * w)
          << ToString(order) << " contact " << q;
      EXPECT_NEAR(r.impulses[2 * q + 1], 0.0, 1e-9 * k * w) << ToString(order) << " contact " << q;
    }
  }
}

// The static step of the bundled N = 3000 packing under its pressure bath: every contact
// moves the cell, the one state that all threads share (each sweeps against its own copy,
// then the changes are summed). Static forces are not unique there, but the cell's balance
// is: Σ cell_arm r_n is the bath's load whatever the network, on one thread or two. Two
// threads give the same bits twice.
double CellLoad(const ContactProblem& p, const Eigen::VectorXd& impulses) {
  double load = 0.0;
  for (int k = 0; k < p.NumContacts(); ++k)
    load += p.contacts[k].cell_arm * impulses[k * p.UnknownsPerContact()];
  return load;
}

TEST(NsgsThreads, KeepTheCellBalanceAndTheirBits) {
  Scene s = ReadPacking(UNJAM_SOURCE_DIR "/problems/pressure-n3000-mu0.5.unjam");
  AssemblyOptions a;
  a.dt = 1.0;
  a.closed_gap_tolerance = 1e-9;
  const ContactProblem p = AssembleProblem(s, DetectContacts(s, 1e-6), a).problem;
  ASSERT_GE(p.NumContacts(), kParallelContacts);
  ASSERT_TRUE(p.cell.has_value());
  SolverOptions o;
  o.tolerance = 1e-5;
  o.nsgs.max_sweeps = 200000;
  const SolveResult one = MakeSolver("nsgs")->Solve(p, o);
  o.nsgs.threads = 2;
  const SolveResult two = MakeSolver("nsgs")->Solve(p, o);
  const SolveResult again = MakeSolver("nsgs")->Solve(p, o);
  ASSERT_TRUE(one.report.converged()) << one.report.residual;
  ASSERT_TRUE(two.report.converged()) << two.report.residual;
  EXPECT_NE(one.impulses, two.impulses);  // another order of updates: another network
  EXPECT_EQ(two.impulses, again.impulses);
  const double load = CellLoad(p, one.impulses);
  ASSERT_GT(load, 0.0);
  EXPECT_NEAR(CellLoad(p, two.impulses), load, 1e-4 * load);
}

// Below kParallelContacts a solve stays on one thread: the same bits as threads = 1.
TEST(NsgsThreads, SmallProblemsStayOnOneThread) {
  const ContactProblem p = StackProblem(50, 0.5);
  SolverOptions o;
  const SolveResult one = MakeSolver("nsgs")->Solve(p, o);
  o.nsgs.threads = 2;
  EXPECT_EQ(MakeSolver("nsgs")->Solve(p, o).impulses, one.impulses);
}

TEST(Registry, UnknownBackendAndBadOptionsSayWhatIsWrong) {
  try {
    MakeSolver("simplex");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nsgs"), std::string::npos);
  }
  // Validate throws for a bad field, naming it.
  auto expect_rejected = [](const SolverOptions& o, const std::string& field) {
    try {
      Validate(o);
      ADD_FAILURE() << field << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  SolverOptions o;
  o.nsgs.relaxation = 2.5;
  expect_rejected(o, "relaxation");
  o = SolverOptions{};
  o.nsgs.threads = 0;
  expect_rejected(o, "threads");
  EXPECT_THROW(SweepOrderFromString("zigzag"), std::invalid_argument);
}

}  // namespace
}  // namespace unjam
