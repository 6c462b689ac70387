#include "unjam/problem/self_stress.hpp"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "unjam/indeterminacy/equilibrium_system.hpp"
#include "unjam/indeterminacy/force_bounds.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {
namespace {

Eigen::SparseMatrix<double> Dense(const Eigen::MatrixXd& m) { return m.sparseView(); }

void ExpectOrthonormalSelfStresses(const Eigen::MatrixXd& s, const Eigen::SparseMatrix<double>& h) {
  EXPECT_LT(
      (s.transpose() * s - Eigen::MatrixXd::Identity(s.cols(), s.cols())).lpNorm<Eigen::Infinity>(),
      1e-12);
  if (s.cols() > 0) {
    EXPECT_LT((Eigen::MatrixXd(h.transpose()) * s).lpNorm<Eigen::Infinity>(), 1e-12);
  }
}

// One body on three supports along one line (three contact rows, one degree of freedom):
// two independent self-stresses, e.g. (1, −1, 0) and (0, 1, −1).
TEST(SelfStress, ThreeSupportsOfOneDegreeOfFreedomHoldTwo) {
  const Eigen::SparseMatrix<double> h = Dense(Eigen::Vector3d(1.0, 1.0, 1.0));
  const SelfStressBasis b = ComputeSelfStresses(h);
  EXPECT_EQ(b.rank, 1);
  ASSERT_EQ(b.dimension(), 2);
  ExpectOrthonormalSelfStresses(b.basis, h);
}

// A statically determinate frame (H square, invertible) has none.
TEST(SelfStress, AnIsostaticNetworkHasNone) {
  Eigen::Matrix3d m;
  m << 1, 0, 0, 1, 1, 0, 0, 1, 1;
  const SelfStressBasis b = ComputeSelfStresses(Dense(m));
  EXPECT_EQ(b.rank, 3);
  EXPECT_EQ(b.dimension(), 0);
}

// Releasing the body's balance: every impulse vector then balances, and the extension adds
// the least-norm one that loads the released column.
TEST(SelfStress, ReleasingABalanceAddsTheImpulsesThatLoadIt) {
  const Eigen::SparseMatrix<double> h = Dense(Eigen::Vector3d(1.0, 1.0, 1.0));
  const Eigen::MatrixXd s = ExtendSelfStresses(ComputeSelfStresses(h).basis, h, {0});
  ASSERT_EQ(s.cols(), 3);
  EXPECT_LT((s.transpose() * s - Eigen::Matrix3d::Identity()).lpNorm<Eigen::Infinity>(), 1e-12);
}

// On the bundled packings the dimension is the degree of force indeterminacy that the
// bounds report (two independent rank estimates of the same balance matrix).
TEST(SelfStress, DimensionIsTheDegreeOfIndeterminacyOfTheBundledPackings) {
  for (const std::string name :
       {"pressure-n500-mu0.5", "pressure-n500-mu0", "gravity-n100-mu0.5"}) {
    const Scene scene = ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/" + name + ".unjam");
    const EquilibriumSystem system = BuildEquilibriumSystem(scene);
    const Eigen::SparseMatrix<double> h = system.matrix.transpose();
    const SelfStressBasis b = ComputeSelfStresses(h);
    EXPECT_EQ(b.dimension(), ForceIndeterminacy(system).dimension) << name;
    EXPECT_LT(b.max_violation, 1e-12) << name;
    ExpectOrthonormalSelfStresses(b.basis, h);
  }
}

}  // namespace
}  // namespace unjam
