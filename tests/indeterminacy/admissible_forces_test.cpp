// Tests for src/indeterminacy/equilibrium_system.cpp, admissible_forces.cpp,
// region_projection.cpp and nearest_lp.cpp: the static certificate on analytic cases.
#include <gtest/gtest.h>

#include <cmath>

#include "test_scenes.hpp"
#include "unjam/indeterminacy/admissible_forces.hpp"
#include "unjam/indeterminacy/equilibrium_system.hpp"

namespace unjam {
namespace {

using testing::Disk;
using testing::Floor;

// The V-groove whose contact normals make the angle α with the vertical.
Scene VGroove(double alpha, double mu) { return testing::VGroove(2.0 * std::sin(alpha), mu); }

TEST(EquilibriumSystem, RowsColumnsAndLoadFollowTheDeclaredEffects) {
  const Scene frictionless = VGroove(0.4, 0.0);
  const EquilibriumSystem a = BuildEquilibriumSystem(frictionless);
  EXPECT_EQ(a.contacts.size(), 2u);
  EXPECT_EQ(a.NumUnknowns(), 2);  // one per contact
  EXPECT_EQ(a.NumRows(), 2);      // no torque row without friction
  EXPECT_DOUBLE_EQ(a.load[1], frictionless.particles[2].Mass());
  const EquilibriumSystem b = BuildEquilibriumSystem(VGroove(0.4, 0.5));
  EXPECT_EQ(b.NumUnknowns(), 4);
  EXPECT_EQ(b.NumRows(), 3);
}

TEST(AdmissibleForces, FrictionlessVGrooveHasTheUniqueAnalyticForces) {
  const double alpha = 0.4;
  const Scene s = VGroove(alpha, 0.0);
  const EquilibriumSystem sys = BuildEquilibriumSystem(s);
  // From no guess at all: the projection finds the unique network.
  const AdmissibleForces a = NearestAdmissibleForces(sys, Eigen::VectorXd::Zero(sys.NumUnknowns()));
  ASSERT_EQ(a.status, AdmissibleStatus::kAdmissible) << a.message;
  const double weight = s.particles[2].Mass();
  for (int k = 0; k < 2; ++k)
    EXPECT_NEAR(a.forces[k], weight / (2.0 * std::cos(alpha)), 1e-13 * weight);
  EXPECT_LT(a.balance_residual, 1e-14);
}

TEST(AdmissibleForces, StackCarriesCumulativeWeightsFromAnyReference) {
  const int k = 6;
  const Scene s = testing::Stack(k, 0.5, 1.0, 0.3);
  const EquilibriumSystem sys = BuildEquilibriumSystem(s);
  ASSERT_EQ(static_cast<int>(sys.contacts.size()), k);
  Eigen::VectorXd noisy = Eigen::VectorXd::Constant(sys.NumUnknowns(), 0.37);
  const AdmissibleForces a = NearestAdmissibleForces(sys, noisy);
  ASSERT_EQ(a.status, AdmissibleStatus::kAdmissible) << a.message;
  const double w = s.particles[0].Mass();
  for (int c = 0; c < k; ++c) {
    const Contact& contact = sys.contacts[c];
    const int below = contact.WithWall() ? -1 : std::min(contact.i, contact.j);
    const int carried = k - 1 - below;  // disks from the upper partner up
    EXPECT_NEAR(std::abs(a.forces[2 * c]), w * carried, 1e-12 * k * w) << "contact " << c;
    EXPECT_NEAR(a.forces[2 * c + 1], 0.0, 1e-12 * w) << "no tangential force in a vertical stack";
  }
}

TEST(AdmissibleForces, FrictionalVGrooveStaysInsideTheConeAndBalances) {
  const Scene s = VGroove(0.3, 0.2);
  const EquilibriumSystem sys = BuildEquilibriumSystem(s);
  Eigen::VectorXd reference = Eigen::VectorXd::Zero(sys.NumUnknowns());
  reference << 3.0, 0.5, 1.0, -0.5;  // unbalanced and partly outside the cone
  const AdmissibleForces a = NearestAdmissibleForces(sys, reference);
  ASSERT_EQ(a.status, AdmissibleStatus::kAdmissible) << a.message;
  for (int c = 0; c < 2; ++c) {
    EXPECT_GE(a.forces[2 * c], 0.0);
    EXPECT_LE(std::abs(a.forces[2 * c + 1]), 0.2 * a.forces[2 * c] * (1.0 + 1e-14));
  }
  EXPECT_LT(a.balance_residual, 1e-13);
}

TEST(AdmissibleForces, ADiskOffTheTopOfAFixedDiskIsNotStatic) {
  Scene s;
  s.cell.size = Vec2(10, 10);
  s.effects.gravity = Vec2(0.0, -1.0);
  const double angle = 0.3;  // contact normal tilted from the vertical: it would roll off
  s.particles = {Disk(0.0, 0.0, 1.0, true),
                 Disk(2.0 * std::sin(angle), 2.0 * std::cos(angle), 1.0)};
  for (double mu : {0.0, 0.5}) {
    s.effects.friction = mu;
    const EquilibriumSystem sys = BuildEquilibriumSystem(s);
    const AdmissibleForces a =
        NearestAdmissibleForces(sys, Eigen::VectorXd::Zero(sys.NumUnknowns()));
    EXPECT_EQ(a.status, AdmissibleStatus::kInfeasible) << "mu " << mu << ": " << a.message;
  }
}

TEST(AdmissibleForces, HyperstaticLatticeUnderPressureMeetsTheVirial) {
  const double r = 0.5;
  const double pressure = 3.0;
  Scene s = testing::TriangularLattice(6, 6, r);
  s.effects.pressure_bath = PressureBath{pressure, 10.0, 0.0};
  const EquilibriumSystem sys = BuildEquilibriumSystem(s);
  ASSERT_EQ(sys.contacts.size(), 3u * s.particles.size());
  // A reference with the wrong pressure and some noise: the nearest network is at P_ext.
  Eigen::VectorXd reference(sys.NumUnknowns());
  for (int k = 0; k < reference.size(); ++k) reference[k] = 1.0 + 0.1 * std::sin(k);
  const AdmissibleForces a = NearestAdmissibleForces(sys, reference);
  ASSERT_EQ(a.status, AdmissibleStatus::kAdmissible) << a.message;
  EXPECT_NEAR(a.forces.mean(), 2.0 * pressure * r / std::sqrt(3.0), 1e-12);
  EXPECT_GE(a.forces.minCoeff(), 0.0);
}

TEST(AdmissibleForces, LinearProgramKeepsAnAdmissibleReferenceAndBalancesAStack) {
  AdmissibleOptions lp;
  lp.method = AdmissibleMethod::kLinearProgram;
  const Scene groove = VGroove(0.3, 0.2);
  const EquilibriumSystem g = BuildEquilibriumSystem(groove);
  const AdmissibleForces exact = NearestAdmissibleForces(g, Eigen::VectorXd::Zero(g.NumUnknowns()));
  ASSERT_EQ(exact.status, AdmissibleStatus::kAdmissible);
  const AdmissibleForces again = NearestAdmissibleForces(g, exact.forces, lp);
  ASSERT_EQ(again.status, AdmissibleStatus::kAdmissible) << again.message;
  EXPECT_EQ(again.method, "linear-program");
  EXPECT_LT((again.forces - exact.forces).lpNorm<Eigen::Infinity>(), 1e-12)
      << "L1 distance 0 is optimal";

  const Scene stack = testing::Stack(4, 0.5, 1.0, 0.0);
  const EquilibriumSystem st = BuildEquilibriumSystem(stack);
  const AdmissibleForces a =
      NearestAdmissibleForces(st, Eigen::VectorXd::Zero(st.NumUnknowns()), lp);
  ASSERT_EQ(a.status, AdmissibleStatus::kAdmissible) << a.message;
  EXPECT_NEAR(a.forces.sum(), stack.particles[0].Mass() * (4 + 3 + 2 + 1), 1e-12);
}

}  // namespace
}  // namespace unjam
