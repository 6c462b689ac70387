// Bounds of a particle shift's critical force on cases with known answers: a stack of disks
// on a floor (lifting the lowest needs exactly the weight above it, with or without
// friction; a lone disk needs none; pushing the top one down meets no upper bound, the
// blocked push of rigid grains), a disk in a V-groove (lifting it opens both supports),
// and the bundled small pile, where the warm-started LPs agree with LPs from scratch.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "test_scenes.hpp"
#include "unjam/indeterminacy/shift_bounds.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/perturbation.hpp"

namespace unjam {
namespace {

using testing::Stack;
using testing::VGroove;

const Vec2 kUp(0.0, 1.0), kDown(0.0, -1.0);

ShiftBounds BoundsOfShift(const Scene& scene, int particle, Vec2 direction) {
  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  const ShiftBoundsReport r = ComputeShiftBounds(s, {{particle, direction}}, {});
  EXPECT_TRUE(r.feasible);
  return r.bounds.at(0);
}

class ShiftBoundsOfAStack : public ::testing::TestWithParam<double> {};

TEST_P(ShiftBoundsOfAStack, LiftingTheLowestDiskNeedsTheWeightAbove) {
  const ShiftBounds b = BoundsOfShift(Stack(3, 1.0, 1.0, GetParam()), 0, kUp);
  ASSERT_TRUE(b.min.ok() && b.max.ok());
  const double weight_above = 2.0 * std::numbers::pi;  // two disks of radius 1, density 1, g = 1
  EXPECT_NEAR(b.min.value, weight_above, 1e-10);
  EXPECT_NEAR(b.max.value, weight_above, 1e-10);
  EXPECT_EQ(b.unloaded_contacts, 1);  // the floor
}

TEST_P(ShiftBoundsOfAStack, LiftingALoneDiskNeedsNoForce) {
  const ShiftBounds b = BoundsOfShift(Stack(1, 1.0, 1.0, GetParam()), 0, kUp);
  ASSERT_TRUE(b.min.ok() && b.max.ok());
  EXPECT_EQ(b.min.value, 0.0);
  EXPECT_EQ(b.max.value, 0.0);
}

TEST_P(ShiftBoundsOfAStack, PushingTheTopDiskDownMeetsNoUpperBound) {
  const ShiftBounds b = BoundsOfShift(Stack(3, 1.0, 1.0, GetParam()), 2, kDown);
  EXPECT_EQ(b.max.status, BoundStatus::kUnbounded);
  ASSERT_TRUE(b.min.ok());
  EXPECT_NEAR(b.min.value, 0.0, 1e-12);  // the disk below may carry it with any force ≥ 0
  EXPECT_EQ(b.unloaded_contacts, 0);
}

INSTANTIATE_TEST_SUITE_P(Friction, ShiftBoundsOfAStack, ::testing::Values(0.0, 0.5));

TEST(ShiftBounds, LiftingADiskOutOfAGrooveOpensBothSupports) {
  const ShiftBounds b = BoundsOfShift(VGroove(1.2, 0.5), 2, kUp);
  EXPECT_EQ(b.unloaded_contacts, 2);
  ASSERT_TRUE(b.min.ok() && b.max.ok());
  EXPECT_EQ(b.min.value, 0.0);
  EXPECT_EQ(b.max.value, 0.0);
}

// The LPs from the unperturbed ensemble's basis and from the slack basis find the same
// bounds, on one thread and on two. Where the shift opens no contact, the stored network is one of
// its admissible networks, and its F_crit lies in [min, max] (a bottom shift unloads the bed, which
// carried the grain: the stored network is then not admissible).
TEST(ShiftBounds, WarmStartsAgreeWithLpsFromScratchOnThePile) {
  const Scene scene =
      ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/gravity-n100-mu0.5.unjam");
  const PerturbationBase base = PreparePerturbations(scene, PerturbationOptions{});
  std::vector<ShiftTarget> shifts;
  for (const auto& targets : {TopTargets(base), BottomTargets(base)}) {
    for (const PerturbationTarget& t : targets) shifts.push_back({t.i, t.direction});
  }
  ASSERT_EQ(shifts.size(), 20u);
  const EquilibriumSystem s = BuildEquilibriumSystem(scene);
  BoundsOptions cold;
  cold.warm_start = false;
  const ShiftBoundsReport warm = ComputeShiftBounds(s, shifts, StoredForcesOf(s, scene.forces));
  const ShiftBoundsReport scratch =
      ComputeShiftBounds(s, shifts, StoredForcesOf(s, scene.forces), cold);
  BoundsOptions two;
  two.threads = 2;
  const ShiftBoundsReport threaded =
      ComputeShiftBounds(s, shifts, StoredForcesOf(s, scene.forces), two);
  ASSERT_TRUE(warm.feasible && scratch.feasible && threaded.feasible);
  int bounded = 0, opened = 0;
  for (std::size_t a = 0; a < shifts.size(); ++a) {
    const ShiftBounds& w = warm.bounds[a];
    const ShiftBounds& c = scratch.bounds[a];
    EXPECT_EQ(w.min.status, c.min.status) << "shift " << a;
    EXPECT_EQ(w.max.status, c.max.status) << "shift " << a;
    if (w.min.ok() && c.min.ok()) {
      EXPECT_NEAR(w.min.value, c.min.value, 1e-8 * (1.0 + std::abs(c.min.value)));
    }
    if (w.max.ok() && c.max.ok()) {
      EXPECT_NEAR(w.max.value, c.max.value, 1e-8 * (1.0 + std::abs(c.max.value)));
    }
    if (w.unloaded_contacts == 0 && w.min.ok()) {
      EXPECT_GE(w.reference, w.min.value - 1e-9);
    }
    if (w.unloaded_contacts == 0 && w.max.ok()) {
      EXPECT_LE(w.reference, w.max.value + 1e-9);
    }
    opened += w.unloaded_contacts > 0;
    bounded += w.min.ok() && w.max.ok();
    // Every shift starts from a copy of the same model: the thread count changes nothing.
    EXPECT_EQ(threaded.bounds[a].min.status, w.min.status);
    EXPECT_EQ(threaded.bounds[a].max.status, w.max.status);
    EXPECT_EQ(threaded.bounds[a].min.value, w.min.value) << "shift " << a;
    EXPECT_EQ(threaded.bounds[a].max.value, w.max.value) << "shift " << a;
  }
  EXPECT_GE(bounded, 15);
  EXPECT_GE(opened, 7);  // most bottom grains rest on the bed
}

}  // namespace
}  // namespace unjam
