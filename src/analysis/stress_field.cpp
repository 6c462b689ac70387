// Coarse-grained stress: each contact's f ⊗ l shared among the boxes its segment crosses.
#include "unjam/analysis/stress_field.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace unjam {

namespace {

// Far beyond any useful resolution; guards the conversion to int.
constexpr double kMaxBoxesPerAxis = 1e8;

// Boxes along one axis of a cell: see CellGrid.
struct AxisTiling {
  double origin = 0.0;
  double side = 0.0;
  int count = 1;
};

AxisTiling TileAxis(bool periodic, double length, double side, double lower, double upper) {
  if (periodic) {
    const double boxes = std::round(length / side);
    if (!(boxes <= kMaxBoxesPerAxis))
      throw std::invalid_argument("CellGrid: too many boxes for this side");
    const int count = std::max(1, static_cast<int>(boxes));
    // side = L / count exactly, so that the boxes tile the periodic cell with no sliver.
    return {0.0, length / count, count};
  }
  if (!std::isfinite(lower) || !std::isfinite(upper) || !(upper >= lower)) {
    throw std::invalid_argument("CellGrid: the extent [lower, upper] must be finite and ordered");
  }
  const double boxes = std::ceil((upper - lower) / side);
  if (boxes > kMaxBoxesPerAxis)
    throw std::invalid_argument("CellGrid: too many boxes for this side");
  const int count = std::max(1, static_cast<int>(boxes));
  return {lower, side, count};
}

void CheckGrid(const GridSpec& grid) {
  if (grid.nx < 1 || grid.ny < 1)
    throw std::invalid_argument("stress grid: nx and ny must be >= 1");
  if (!(grid.side.x() > 0.0) || !(grid.side.y() > 0.0) || !grid.side.allFinite() ||
      !grid.origin.allFinite()) {
    throw std::invalid_argument("stress grid: box sides must be positive and finite");
  }
}

// Parameters t in (0, 1) where start + t·delta (in box units) crosses an integer grid line
// along one axis.
void AppendCrossings(double start, double delta, std::vector<double>& t) {
  if (delta == 0.0) return;
  const double end = start + delta;
  const double first = std::floor(std::min(start, end)) + 1.0;
  const double last = std::ceil(std::max(start, end)) - 1.0;
  for (double line = first; line <= last; line += 1.0) {
    const double crossing = (line - start) / delta;
    if (crossing > 0.0 && crossing < 1.0) t.push_back(crossing);
  }
}

// The box index along one axis of a point at u (in box units), wrapped on a periodic axis;
// -1 when the point is outside a non-periodic grid.
int AxisBox(double u, int count, bool periodic) {
  const double cell = std::floor(u);
  if (periodic) {
    const double wrapped = cell - count * std::floor(cell / count);
    return std::clamp(static_cast<int>(wrapped), 0, count - 1);
  }
  return cell >= 0.0 && cell < count ? static_cast<int>(cell) : -1;
}

void CheckSegment(const StressSegment& s) {
  if (!s.start.allFinite() || !s.branch.allFinite() || !s.force.allFinite()) {
    throw std::invalid_argument(
        "CoarseGrainedStress: segment with a non-finite start, branch or force");
  }
}

// Adds one segment's f ⊗ l to the boxes it crosses, each in proportion to the length of
// the segment inside it. Sub-intervals between successive grid-line crossings lie in one
// box each; their midpoints locate that box without any test exactly on a grid line.
void AddSegment(const StressSegment& s, double box_area, StressGrid& out) {
  const double length = s.branch.norm();
  if (length == 0.0) return;  // f ⊗ 0 = 0: nothing to share
  const GridSpec& grid = out.grid;
  const Vec2 u0 = (s.start - grid.origin).cwiseQuotient(grid.side);
  const Vec2 du = s.branch.cwiseQuotient(grid.side);

  std::vector<double> t = {0.0, 1.0};
  AppendCrossings(u0.x(), du.x(), t);
  AppendCrossings(u0.y(), du.y(), t);
  std::sort(t.begin(), t.end());

  const Eigen::Matrix2d share_per_unit_t = s.force * s.branch.transpose() / box_area;
  for (std::size_t k = 0; k + 1 < t.size(); ++k) {
    const double fraction = t[k + 1] - t[k];  // θ / |l| of this piece
    if (fraction <= 0.0) continue;            // a corner: both lines crossed at once
    const Vec2 mid = u0 + 0.5 * (t[k] + t[k + 1]) * du;
    const int ix = AxisBox(mid.x(), grid.nx, grid.periodic_x);
    const int iy = AxisBox(mid.y(), grid.ny, grid.periodic_y);
    if (ix < 0 || iy < 0) {
      out.lost_length += fraction * length;
      continue;
    }
    out.stress[iy * grid.nx + ix] += fraction * share_per_unit_t;
  }
}

}  // namespace

GridSpec CellGrid(const Cell& cell, double side, Vec2 lower, Vec2 upper) {
  if (!(side > 0.0) || !std::isfinite(side))
    throw std::invalid_argument("CellGrid: side must be positive");
  const AxisTiling x =
      TileAxis(PeriodicX(cell.periodicity), cell.size.x(), side, lower.x(), upper.x());
  const AxisTiling y =
      TileAxis(PeriodicY(cell.periodicity), cell.size.y(), side, lower.y(), upper.y());
  GridSpec grid;
  grid.origin = Vec2(x.origin, y.origin);
  grid.side = Vec2(x.side, y.side);
  grid.nx = x.count;
  grid.ny = y.count;
  grid.periodic_x = PeriodicX(cell.periodicity);
  grid.periodic_y = PeriodicY(cell.periodicity);
  return grid;
}

StressGrid CoarseGrainedStress(const GridSpec& grid, const std::vector<StressSegment>& segments) {
  CheckGrid(grid);
  StressGrid out;
  out.grid = grid;
  out.stress.assign(static_cast<std::size_t>(grid.nx) * grid.ny, Eigen::Matrix2d::Zero());
  const double box_area = grid.side.x() * grid.side.y();
  for (const StressSegment& s : segments) {
    CheckSegment(s);
    AddSegment(s, box_area, out);
  }
  return out;
}

double Pressure(const Eigen::Matrix2d& sigma) { return 0.5 * sigma.trace(); }

double MaxShear(const Eigen::Matrix2d& sigma) {
  const double half_difference = 0.5 * (sigma(0, 0) - sigma(1, 1));
  // The shear of the symmetric part: a contact sum out of equilibrium (or with rounding)
  // is not exactly symmetric, and only the symmetric part has principal stresses.
  const double shear = 0.5 * (sigma(0, 1) + sigma(1, 0));
  return std::hypot(half_difference, shear);
}

}  // namespace unjam
