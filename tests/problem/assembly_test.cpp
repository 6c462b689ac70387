// Tests for src/problem/assembly.cpp, contact_problem.cpp and kinematics.cpp: the scene's
// effects become exactly the terms they declare, and the loop kinematics equal the sparse
// matrices.
#include <gtest/gtest.h>

#include <random>

#include <Eigen/Eigenvalues>

#include "test_scenes.hpp"
#include "unjam/problem/assembly.hpp"
#include "unjam/problem/kinematics.hpp"

namespace unjam {
namespace {

using testing::Disk;

Scene Pair(double mu) {
  Scene s;
  s.cell.size = Vec2(10, 10);
  s.effects.friction = mu;
  // Disks 0 and 1 overlap by 0.1; the fixed disk 2 is far away.
  s.particles = {Disk(1.0, 1.0, 0.5), Disk(1.9, 1.0, 0.5), Disk(3.0, 3.0, 0.5, true)};
  return s;
}

AssembledProblem Assemble(const Scene& s) {
  return AssembleProblem(s, DetectContacts(s, 0.5), AssemblyOptions{});
}

TEST(Assembly, FrictionlessSceneHasOneUnknownPerContactAndNoRotation) {
  const AssembledProblem a = Assemble(Pair(0.0));
  EXPECT_FALSE(a.problem.frictional);
  EXPECT_EQ(a.problem.NumContacts(), 1);
  EXPECT_EQ(a.problem.NumUnknowns(), 1);
  EXPECT_EQ(a.problem.NumBodies(), 2);  // the fixed disk has no degrees of freedom
  EXPECT_EQ(a.problem.NumDofs(), 4);    // translations only
  EXPECT_TRUE(a.problem.inv_inertia.empty());
  EXPECT_FALSE(a.problem.cell.has_value());
  EXPECT_EQ(AssembleJacobian(a.problem).rows(), 1);
}

TEST(Assembly, FrictionalSceneAddsTangentsAndRotations) {
  const AssembledProblem a = Assemble(Pair(0.4));
  EXPECT_EQ(a.problem.NumUnknowns(), 2);
  EXPECT_EQ(a.problem.NumDofs(), 6);
  EXPECT_DOUBLE_EQ(a.problem.contacts[0].mu, 0.4);
}

TEST(Assembly, GravityIsTheOnlySourceOfFreeVelocity) {
  Scene s = Pair(0.0);
  EXPECT_EQ(Assemble(s).problem.free_velocity[0], Vec2::Zero());
  s.effects.gravity = Vec2(0.0, -2.0);
  AssemblyOptions o;
  o.dt = 0.01;
  EXPECT_EQ(AssembleProblem(s, {}, o).problem.free_velocity[0], Vec2(0.0, -0.02));
}

// The height of a contact point against gravity, read only by NSGS's height order: the
// point of contact of disks 0 and 1 (centres (1, 1) and (1.9, 1), radius 0.5, overlapping)
// lies on the line between them at R from disk 0.
TEST(Assembly, ContactHeightIsMeasuredAgainstGravityAndZeroWithout) {
  Scene s = Pair(0.0);
  EXPECT_EQ(Assemble(s).problem.contacts[0].height, 0.0);
  s.effects.gravity = Vec2(0.0, -2.0);
  EXPECT_DOUBLE_EQ(Assemble(s).problem.contacts[0].height, 1.0);
  s.effects.gravity = Vec2(3.0, 0.0);  // gravity along +x: height is −x of the point
  EXPECT_DOUBLE_EQ(Assemble(s).problem.contacts[0].height, -1.5);
}

TEST(Assembly, PressureBathAddsOneCellDegreeOfFreedom) {
  Scene s = testing::TriangularLattice(4, 4, 0.5);
  EXPECT_EQ(Assemble(s).problem.NumDofs(), 2 * 16);
  s.effects.pressure_bath = PressureBath{2.0, 50.0, 0.0};
  const AssembledProblem a = Assemble(s);
  ASSERT_TRUE(a.problem.cell.has_value());
  EXPECT_EQ(a.problem.NumDofs(), 2 * 16 + 1);
  const double volume = s.cell.size.x() * s.cell.size.y();
  EXPECT_DOUBLE_EQ(a.problem.cell->inv_mass, 1.0 / (50.0 * 2.0 * volume));
  EXPECT_DOUBLE_EQ(a.problem.cell->free_rate, -1e-3 * 2.0 / 50.0);
  for (const ProblemContact& c : a.problem.contacts) EXPECT_NEAR(c.cell_arm, 1.0, 1e-12);
}

TEST(Assembly, PrescribedMotionRemovesTheBodyAndEntersTheBias) {
  Scene s = Pair(0.5);
  s.effects.prescribed_motion.push_back({0, Vec2(1.0, 2.0), 0.5});
  const AssembledProblem a = Assemble(s);
  EXPECT_EQ(a.problem.NumBodies(), 1);
  ASSERT_EQ(a.problem.NumContacts(), 1);
  // Normal (1, 0): side i moving at (1, 2) closes the gap at 1 and shears at −2 − R ω.
  EXPECT_DOUBLE_EQ(a.problem.contacts[0].bias.x(), -1.0);
  EXPECT_DOUBLE_EQ(a.problem.contacts[0].bias.y(), -2.0 - 0.5 * 0.5);
}

TEST(Assembly, PrescribedGapMakesABilateralFrictionlessContact) {
  Scene s = Pair(0.5);
  s.effects.prescribed_gaps.push_back({1, 0, {0, 0}, 1e-9});  // named in either order
  std::vector<Contact> contacts = DetectContacts(s, 0.5);
  EnsurePrescribedContacts(s, contacts);
  const AssembledProblem a = AssembleProblem(s, contacts, AssemblyOptions{});
  ASSERT_EQ(a.problem.NumContacts(), 1);
  EXPECT_EQ(a.problem.contacts[0].kind, ConstraintKind::kBilateral);
  EXPECT_EQ(a.problem.contacts[0].mu, 0.0);
  EXPECT_NEAR(a.problem.contacts[0].target_velocity, (1e-9 + 0.1) / 1e-3, 1e-9);
}

TEST(Assembly, FarPrescribedGapIsAddedToTheContacts) {
  Scene s = Pair(0.0);
  s.particles[1].position.x() = 2.1;
  s.effects.prescribed_gaps.push_back({0, 1, {0, 0}, 0.0});
  std::vector<Contact> contacts = DetectContacts(s, 0.0);  // the pair is 0.1 apart
  EXPECT_TRUE(contacts.empty());
  EnsurePrescribedContacts(s, contacts);
  ASSERT_EQ(contacts.size(), 1u);
  s.effects.prescribed_gaps[0].j = 7;
  EXPECT_THROW(EnsurePrescribedContacts(s, contacts), std::invalid_argument);
}

// A random frictional problem with walls, fixed disks, prescribed motion and a cell.
ContactProblem RandomProblem(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Scene s;
  s.cell.size = Vec2(6.0, 6.0);
  s.cell.periodicity = Periodicity::kXY;
  s.effects.friction = 0.3;
  s.effects.gravity = Vec2(0.1, -1.0);
  s.effects.pressure_bath = PressureBath{1.0, 10.0, 0.01};
  for (int i = 0; i < 36; ++i) {
    Particle p =
        Disk(0.5 + i % 6 + 0.05 * u(rng), 0.5 + i / 6 + 0.05 * u(rng), 0.5 + 0.02 * u(rng), i == 3);
    p.velocity = Vec2(u(rng), u(rng));
    p.spin = u(rng);
    s.particles.push_back(p);
  }
  s.effects.prescribed_motion.push_back({7, Vec2(0.3, -0.2), 0.1});
  return AssembleProblem(s, DetectContacts(s, 0.1), AssemblyOptions{}).problem;
}

TEST(Kinematics, LoopVelocitiesEqualTheSparseMatrices) {
  const ContactProblem p = RandomProblem(7);
  ASSERT_GT(p.NumContacts(), 40);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd r(p.NumUnknowns());
  for (int i = 0; i < r.size(); ++i) r[i] = u(rng);
  const Eigen::VectorXd v_sparse = EndVelocity(p, r);
  const VelocityState v_loop = EndVelocityState(p, r);
  for (int b = 0; b < p.NumBodies(); ++b) {
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(v_loop.body[b][d], v_sparse[3 * b + d], 1e-13);
  }
  EXPECT_NEAR(v_loop.cell_rate, v_sparse[p.NumDofs() - 1], 1e-15);
  const Eigen::VectorXd u_sparse = PosedContactVelocity(p, r);
  const Eigen::VectorXd u_delassus = AssembleDelassus(p) * r + DelassusOffset(p);
  for (int k = 0; k < p.NumContacts(); ++k) {
    const Eigen::Vector2d u_loop = PosedVelocity(p, v_loop, k);
    EXPECT_NEAR(u_loop[0], u_sparse[2 * k], 1e-12);
    EXPECT_NEAR(u_loop[1], u_sparse[2 * k + 1], 1e-12);
    EXPECT_NEAR(u_delassus[2 * k], u_sparse[2 * k], 1e-11);
  }
}

TEST(Kinematics, DelassusIsSymmetricPositiveSemidefinite) {
  const ContactProblem p = RandomProblem(11);
  const Eigen::MatrixXd w = Eigen::MatrixXd(AssembleDelassus(p));
  EXPECT_LT((w - w.transpose()).norm(), 1e-14 * w.norm());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(w);
  EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-12 * w.norm());
}

}  // namespace
}  // namespace unjam
