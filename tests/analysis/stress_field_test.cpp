// Tests for src/analysis/stress_field.cpp
#include "unjam/analysis/stress_field.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

namespace unjam {
namespace {

GridSpec Grid(double side, int nx, int ny, bool periodic_x = false, bool periodic_y = false) {
  GridSpec g;
  g.origin = Vec2::Zero();
  g.side = Vec2(side, side);
  g.nx = nx;
  g.ny = ny;
  g.periodic_x = periodic_x;
  g.periodic_y = periodic_y;
  return g;
}

StressSegment Segment(Vec2 start, Vec2 branch, Vec2 force) {
  return StressSegment{start, branch, force};
}

Eigen::Matrix2d Outer(const Vec2& f, const Vec2& l) { return f * l.transpose(); }

// The share of the whole f ⊗ l / A that box (ix, iy) received, read off one component.
double Fraction(const StressGrid& s, int ix, int iy, const StressSegment& seg) {
  const double area = s.grid.side.x() * s.grid.side.y();
  return s.at(ix, iy)(0, 0) / (seg.force.x() * seg.branch.x() / area);
}

// A · Σ_boxes σ_box: the total virial the grid holds.
Eigen::Matrix2d GridVirial(const StressGrid& s) {
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  for (const Eigen::Matrix2d& box : s.stress) sum += box;
  return sum * s.grid.side.x() * s.grid.side.y();
}

TEST(StressField, SegmentInsideOneBox) {
  const StressSegment seg = Segment(Vec2(0.5, 0.5), Vec2(1.0, 0.8), Vec2(2.0, -1.0));
  const StressGrid s = CoarseGrainedStress(Grid(2.0, 3, 2), {seg});
  ASSERT_EQ(s.stress.size(), 6u);
  const Eigen::Matrix2d expected = Outer(seg.force, seg.branch) / 4.0;
  EXPECT_TRUE(s.at(0, 0).isApprox(expected, 1e-15)) << s.at(0, 0);
  EXPECT_EQ(s.at(0, 0)(0, 1), 2.0 * 0.8 / 4.0);  // f_x l_y: the order of the outer product
  for (int iy = 0; iy < 2; ++iy) {
    for (int ix = 0; ix < 3; ++ix) {
      if (ix == 0 && iy == 0) continue;
      EXPECT_TRUE(s.at(ix, iy).isZero(0.0)) << ix << ' ' << iy;
    }
  }
  EXPECT_EQ(s.lost_length, 0.0);
  EXPECT_EQ(s.BoxCenter(2, 1), Vec2(5.0, 3.0));
}

TEST(StressField, SegmentAlongXSplitsByLength) {
  const StressSegment seg = Segment(Vec2(0.25, 0.5), Vec2(2.0, 0.0), Vec2(1.0, 0.5));
  const StressGrid s = CoarseGrainedStress(Grid(1.0, 4, 1), {seg});
  EXPECT_NEAR(Fraction(s, 0, 0, seg), 0.375, 1e-15);  // 0.75 of 2
  EXPECT_NEAR(Fraction(s, 1, 0, seg), 0.5, 1e-15);
  EXPECT_NEAR(Fraction(s, 2, 0, seg), 0.125, 1e-15);
  EXPECT_EQ(s.at(3, 0)(0, 0), 0.0);
}

TEST(StressField, DiagonalSegmentSplitsByLength) {
  // Crosses x = 1 at t = 0.5 (y = 0.75), then y = 1 at t = 0.75 (x = 1.25).
  const StressSegment seg = Segment(Vec2(0.5, 0.25), Vec2(1.0, 1.0), Vec2(1.0, 1.0));
  const StressGrid s = CoarseGrainedStress(Grid(1.0, 2, 2), {seg});
  EXPECT_NEAR(Fraction(s, 0, 0, seg), 0.5, 1e-15);
  EXPECT_NEAR(Fraction(s, 1, 0, seg), 0.25, 1e-15);
  EXPECT_NEAR(Fraction(s, 1, 1, seg), 0.25, 1e-15);
  EXPECT_EQ(Fraction(s, 0, 1, seg), 0.0);
}

TEST(StressField, SegmentThroughACornerSkipsTheSideBoxes) {
  const StressSegment seg = Segment(Vec2(0.5, 0.5), Vec2(1.0, 1.0), Vec2(1.0, 1.0));
  const StressGrid s = CoarseGrainedStress(Grid(1.0, 2, 2), {seg});
  EXPECT_NEAR(Fraction(s, 0, 0, seg), 0.5, 1e-15);
  EXPECT_NEAR(Fraction(s, 1, 1, seg), 0.5, 1e-15);
  EXPECT_EQ(Fraction(s, 1, 0, seg), 0.0);
  EXPECT_EQ(Fraction(s, 0, 1, seg), 0.0);
}

TEST(StressField, SegmentOnAGridLineGoesToOneSide) {
  // Lies on x = 1: the whole share must land in exactly one column, not be lost or doubled.
  const StressSegment seg = Segment(Vec2(1.0, 0.2), Vec2(0.0, 0.5), Vec2(0.0, 3.0));
  const StressGrid s = CoarseGrainedStress(Grid(1.0, 2, 1), {seg});
  EXPECT_TRUE(GridVirial(s).isApprox(Outer(seg.force, seg.branch), 1e-15));
  EXPECT_EQ(s.lost_length, 0.0);
}

TEST(StressField, SegmentAcrossThePeriodicBoundaryWraps) {
  // Cell 10 × 7 in 8 × 5 boxes of 1.25 × 1.4. From (9.5, 6.8) along (1, 0.5): y = 7 at t = 0.4,
  // x = 10 at t = 0.5.
  GridSpec g = Grid(1.0, 8, 5, true, true);
  g.side = Vec2(1.25, 1.4);
  const StressSegment seg = Segment(Vec2(9.5, 6.8), Vec2(1.0, 0.5), Vec2(2.0, 1.0));
  const StressGrid s = CoarseGrainedStress(g, {seg});
  EXPECT_NEAR(Fraction(s, 7, 4, seg), 0.4, 1e-14);
  EXPECT_NEAR(Fraction(s, 7, 0, seg), 0.1, 1e-14);
  EXPECT_NEAR(Fraction(s, 0, 0, seg), 0.5, 1e-14);
  EXPECT_EQ(s.lost_length, 0.0);
}

TEST(StressField, SegmentLeavingThroughTheLowerSideWraps) {
  // From x = 0.3 back to x = −0.3: half in column 0, half in the last column.
  GridSpec g = Grid(1.0, 8, 5, true, true);
  g.side = Vec2(1.25, 1.4);
  const StressSegment seg = Segment(Vec2(0.3, 0.7), Vec2(-0.6, 0.0), Vec2(-1.0, 0.0));
  const StressGrid s = CoarseGrainedStress(g, {seg});
  EXPECT_NEAR(Fraction(s, 0, 0, seg), 0.5, 1e-15);
  EXPECT_NEAR(Fraction(s, 7, 0, seg), 0.5, 1e-15);
}

TEST(StressField, PeriodicGridHoldsTheWholeVirial) {
  Cell cell;
  cell.size = Vec2(10.0, 7.0);
  cell.periodicity = Periodicity::kXY;
  const GridSpec g = CellGrid(cell, 1.3, Vec2::Zero(), Vec2::Zero());
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<StressSegment> segments;
  Eigen::Matrix2d virial = Eigen::Matrix2d::Zero();
  for (int k = 0; k < 500; ++k) {
    const Vec2 start(10.0 * unit(rng), 7.0 * unit(rng));
    const double angle = 2.0 * std::numbers::pi * unit(rng);
    // Mostly contact-sized, some longer than the cell (wrapping several times).
    const double length = k % 50 == 0 ? 25.0 * unit(rng) : 3.0 * unit(rng);
    const Vec2 branch = length * Vec2(std::cos(angle), std::sin(angle));
    const Vec2 force(2.0 * unit(rng) - 1.0, 2.0 * unit(rng) - 1.0);
    segments.push_back(Segment(start, branch, force));
    virial += Outer(force, branch);
  }
  int crossing = 0;
  for (const StressSegment& seg : segments) {
    const Vec2 end = seg.start + seg.branch;
    if (end.x() < 0.0 || end.x() >= 10.0 || end.y() < 0.0 || end.y() >= 7.0) ++crossing;
  }
  ASSERT_GT(crossing, 20);  // the boundary is really exercised
  const StressGrid s = CoarseGrainedStress(g, segments);
  EXPECT_LT((GridVirial(s) - virial).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(s.lost_length, 0.0);
}

TEST(StressField, NonPeriodicGridDropsTheOutsidePart) {
  const StressSegment half_out = Segment(Vec2(1.5, 1.5), Vec2(1.0, 0.0), Vec2(4.0, 0.0));
  const StressSegment all_out = Segment(Vec2(-3.0, -3.0), Vec2(0.0, 2.0), Vec2(0.0, 1.0));
  const StressSegment below = Segment(Vec2(0.5, 0.5), Vec2(0.0, -1.5), Vec2(0.0, 1.0));
  const StressGrid s = CoarseGrainedStress(Grid(1.0, 2, 2), {half_out, all_out, below});
  EXPECT_NEAR(Fraction(s, 1, 1, half_out), 0.5, 1e-15);
  EXPECT_NEAR(s.at(0, 0)(1, 1), (1.0 / 3.0) * (1.0 * -1.5), 1e-15);  // 0.5 of 1.5 inside
  EXPECT_NEAR(s.lost_length, 0.5 + 2.0 + 1.0, 1e-15);
}

TEST(StressField, MixedPeriodicityWrapsXAndDropsY) {
  GridSpec g = Grid(1.0, 3, 2, true, false);
  // Leaves through x = 3 (wraps into column 0) and through y = 2 (dropped).
  const StressSegment seg = Segment(Vec2(2.5, 1.5), Vec2(1.0, 1.0), Vec2(1.0, 0.0));
  const StressGrid s = CoarseGrainedStress(g, {seg});
  EXPECT_NEAR(Fraction(s, 2, 1, seg), 0.5, 1e-15);
  EXPECT_EQ(Fraction(s, 0, 1, seg), 0.0);  // after x wraps, y ≥ 2: outside
  EXPECT_NEAR(s.lost_length, 0.5 * std::sqrt(2.0), 1e-15);
}

TEST(StressField, ZeroLengthSegmentContributesNothing) {
  const StressGrid s = CoarseGrainedStress(
      Grid(1.0, 2, 2), {Segment(Vec2(-5.0, 0.5), Vec2::Zero(), Vec2(1.0, 1.0))});
  for (const Eigen::Matrix2d& box : s.stress) EXPECT_TRUE(box.isZero(0.0));
  EXPECT_EQ(s.lost_length, 0.0);
}

TEST(StressField, BadInputThrows) {
  EXPECT_THROW(CoarseGrainedStress(Grid(1.0, 0, 2), {}), std::invalid_argument);
  EXPECT_THROW(CoarseGrainedStress(Grid(0.0, 2, 2), {}), std::invalid_argument);
  const StressSegment nan_segment =
      Segment(Vec2(std::numeric_limits<double>::quiet_NaN(), 0.0), Vec2(1.0, 0.0), Vec2(1.0, 0.0));
  EXPECT_THROW(CoarseGrainedStress(Grid(1.0, 2, 2), {nan_segment}), std::invalid_argument);
  EXPECT_THROW(CellGrid(Cell{}, 0.0, Vec2::Zero(), Vec2::Ones()), std::invalid_argument);
}

TEST(StressCellGrid, TilesAPeriodicCellExactly) {
  Cell cell;
  cell.size = Vec2(10.0, 7.0);
  cell.periodicity = Periodicity::kXY;
  const GridSpec g = CellGrid(cell, 1.3, Vec2(3.0, 3.0), Vec2(4.0, 4.0));  // extent unused
  EXPECT_EQ(g.nx, 8);                                                      // round(7.69)
  EXPECT_EQ(g.ny, 5);                                                      // round(5.38)
  EXPECT_EQ(g.origin, Vec2::Zero());
  EXPECT_EQ(g.side.x(), 10.0 / 8);
  EXPECT_EQ(g.side.y(), 7.0 / 5);
  EXPECT_NEAR(g.nx * g.side.x(), 10.0, 1e-15);
  EXPECT_NEAR(g.ny * g.side.y(), 7.0, 1e-14);
  EXPECT_TRUE(g.periodic_x);
  EXPECT_TRUE(g.periodic_y);
}

TEST(StressCellGrid, LargeSideGivesOneBox) {
  Cell cell;
  cell.size = Vec2(3.0, 3.0);
  cell.periodicity = Periodicity::kXY;
  const GridSpec g = CellGrid(cell, 100.0, Vec2::Zero(), Vec2::Zero());
  EXPECT_EQ(g.nx, 1);
  EXPECT_EQ(g.ny, 1);
  EXPECT_EQ(g.side, Vec2(3.0, 3.0));
}

TEST(StressCellGrid, NonPeriodicAxisSpansTheDisks) {
  Cell cell;
  cell.size = Vec2(10.0, 50.0);
  cell.periodicity = Periodicity::kX;
  const GridSpec g = CellGrid(cell, 1.3, Vec2(0.0, -0.5), Vec2(10.0, 4.2));
  EXPECT_EQ(g.nx, 8);
  EXPECT_EQ(g.side.x(), 1.25);
  EXPECT_EQ(g.ny, 4);  // ceil(4.7 / 1.3)
  EXPECT_EQ(g.side.y(), 1.3);
  EXPECT_EQ(g.origin.y(), -0.5);
  EXPECT_TRUE(g.periodic_x);
  EXPECT_FALSE(g.periodic_y);

  cell.periodicity = Periodicity::kNone;
  const GridSpec none = CellGrid(cell, 2.0, Vec2(1.0, 2.0), Vec2(5.0, 3.0));
  EXPECT_EQ(none.origin, Vec2(1.0, 2.0));
  EXPECT_EQ(none.nx, 2);
  EXPECT_EQ(none.ny, 1);
  EXPECT_FALSE(none.periodic_x);
}

TEST(StressInvariants, PressureAndMaxShear) {
  Eigen::Matrix2d diag;
  diag << 3.0, 0.0, 0.0, 1.0;
  EXPECT_EQ(Pressure(diag), 2.0);
  EXPECT_EQ(MaxShear(diag), 1.0);
  Eigen::Matrix2d shear;
  shear << 1.0, 2.0, 2.0, 1.0;
  EXPECT_EQ(Pressure(shear), 1.0);
  EXPECT_EQ(MaxShear(shear), 2.0);
  // Both are invariant under rotation.
  const double c = std::cos(0.7), s = std::sin(0.7);
  Eigen::Matrix2d rotation;
  rotation << c, -s, s, c;
  const Eigen::Matrix2d rotated = rotation * diag * rotation.transpose();
  EXPECT_NEAR(Pressure(rotated), 2.0, 1e-15);
  EXPECT_NEAR(MaxShear(rotated), 1.0, 1e-15);
}

}  // namespace
}  // namespace unjam
