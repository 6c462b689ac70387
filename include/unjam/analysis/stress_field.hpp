// Coarse-grained stress on a grid of boxes.
//
// Each contact contributes the tensor f ⊗ l (f the contact force on j, l the centre-to-
// centre vector from i to j, periodic image included). The tensor is split among the
// boxes crossed by the segment from x_i to x_i + l in proportion to the length of the
// segment inside each box (θ_ij), and each box's share is divided by the box area:
//     σ_box = (1/A_box) Σ_contacts (θ_ij,box / |l|) f ⊗ l.
// Summed over boxes and multiplied by A_box this is exactly the virial Σ f ⊗ l when no
// segment leaves the grid (the test of the splitting). Along a periodic axis of the grid,
// box indices wrap (a segment leaving on one side enters on the other); along a
// non-periodic axis the parts of segments outside the grid are dropped and counted in
// `lost_length`.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "unjam/scene/scene.hpp"

namespace unjam {

struct GridSpec {
  Vec2 origin = Vec2::Zero();  // lower-left corner of box (0, 0)
  Vec2 side = Vec2(2.0, 2.0);  // box sides along x and y
  int nx = 1, ny = 1;
  bool periodic_x = false, periodic_y = false;

  Vec2 BoxCenter(int ix, int iy) const {
    return origin + Vec2((ix + 0.5) * side.x(), (iy + 0.5) * side.y());
  }
  Vec2 BoxCenter(int box) const { return BoxCenter(box % nx, box / nx); }  // box = iy · nx + ix
};

// The grid that tiles a cell with boxes as close to `side` as possible: along a periodic
// axis count = max(1, round(L / side)) and side = L / count exactly; along a non-periodic
// axis the grid spans [lower, upper) with the given side (count = ceil((upper − lower) /
// side)), lower/upper being the extent of the disks along that axis.
GridSpec CellGrid(const Cell& cell, double side, Vec2 lower, Vec2 upper);

// One contact's segment and force (force on j, l = x_j + image shift − x_i).
struct StressSegment {
  Vec2 start = Vec2::Zero();   // x_i
  Vec2 branch = Vec2::Zero();  // l
  Vec2 force = Vec2::Zero();   // f = f_n n + f_t t
};

struct StressGrid {
  GridSpec grid;
  std::vector<Eigen::Matrix2d> stress;  // box (ix, iy) at index iy · nx + ix
  double lost_length = 0.0;             // segment length dropped outside the grid

  const Eigen::Matrix2d& at(int ix, int iy) const { return stress[iy * grid.nx + ix]; }
  Vec2 BoxCenter(int ix, int iy) const { return grid.BoxCenter(ix, iy); }
};

StressGrid CoarseGrainedStress(const GridSpec& grid, const std::vector<StressSegment>& segments);

// Pressure P = ½ tr σ (positive in compression with the sign convention f_n > 0 repulsive)
// and the maximal shear stress τ_max = √(((σxx − σyy)/2)² + σxy²).
double Pressure(const Eigen::Matrix2d& sigma);
double MaxShear(const Eigen::Matrix2d& sigma);

}  // namespace unjam
