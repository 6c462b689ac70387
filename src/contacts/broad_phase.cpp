// Cell-list broad phase: contacts in O(N), bit-identical to DetectContactsBruteForce.
//
// Particles are binned into a grid of cells at least as wide as the contact reach
// 2 R_max + margin, so every pair within reach lies in the same or in adjacent cells. Each
// particle i scans its own cell and its 8 neighbours (full stencil, keeping j > i only):
// unlike a half-shell stencil this stays correct without special cases when a periodic axis
// has only one or two cells, where neighbours in both directions are the same cell seen
// through different images. Every accepted pair goes through MakeContact with the stored
// positions, exactly as the reference does, so the output bits agree.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "minimum_image.hpp"
#include "unjam/contacts/contact.hpp"

namespace unjam {
namespace {

// One axis of the grid. Along a periodic axis the cells tile [0, L) exactly (width L/count)
// so that wrapping a cell index by count is the same as shifting by one period; along an
// open axis they tile the bounding box of the particles.
struct Axis {
  bool periodic = false;
  double origin = 0.0;
  double extent = 0.0;  // period, or bounding-box size
  double width = 1.0;
  int count = 1;
};

void SetCount(Axis& axis, int count, double min_width) {
  axis.count = count;
  // A single open cell has no neighbours; its width only has to be positive.
  const bool tiled = count > 1 || axis.periodic;
  axis.width = tiled ? axis.extent / count : std::max(axis.extent, min_width);
}

Axis MakeAxis(bool periodic, double origin, double extent, double min_width, double max_cells) {
  Axis axis;
  axis.periodic = periodic;
  axis.origin = origin;
  axis.extent = extent;
  // Clamp in floating point first: a huge sparse domain would overflow an int.
  const double fit = std::clamp(std::floor(extent / min_width), 1.0, max_cells);
  SetCount(axis, static_cast<int>(fit), min_width);
  return axis;
}

// A particle as the search loop sees it, stored contiguously in cell order so that the
// inner loop streams through memory instead of jumping around scene.particles.
struct Entry {
  double x = 0.0;  // stored (not wrapped) position: the geometry uses it as is
  double y = 0.0;
  double radius = 0.0;
  int index = 0;
  int cell = 0;
  std::array<int, 2> wrap = {0, 0};  // stored position = binned position + wrap ⊙ L
  bool fixed = false;
};

// Reused between calls (detection runs every time step) to avoid reallocating.
struct Workspace {
  std::vector<int> cell_of;                 // per particle
  std::vector<std::array<int, 2>> wrap_of;  // per particle, see Entry::wrap
  std::vector<int> run_begin;               // per particle: its pair contacts in `pairs`
  std::vector<int> run_end;
  std::vector<int> cell_start;  // CSR offsets into `entries`, one past the end at the back
  std::vector<Entry> entries;
  std::vector<Contact> pairs;  // grouped by i, the groups in cell order
  std::size_t last_contact_count = 0;
};

// Cell index along one axis, and the number of periods removed to bin the coordinate.
// Rounding may put a coordinate on the wrong side of a cell boundary by an ulp; the search
// tolerates that (cells are slightly wider than the reach), so clamping is enough.
int Bin(const Axis& axis, double coordinate, int& wrap) {
  double local = coordinate - axis.origin;
  wrap = 0;
  if (axis.periodic) {
    const double periods = std::clamp(std::floor(local / axis.extent), -1e9, 1e9);
    wrap = static_cast<int>(periods);
    local -= periods * axis.extent;
  }
  const double cell = std::floor(local / axis.width);
  return static_cast<int>(std::clamp(cell, 0.0, static_cast<double>(axis.count - 1)));
}

std::array<Axis, 2> MakeGrid(const Scene& scene, double reach) {
  const auto& particles = scene.particles;
  Vec2 lo = particles.front().position;
  Vec2 hi = lo;
  for (const Particle& p : particles) {
    lo = lo.cwiseMin(p.position);
    hi = hi.cwiseMax(p.position);
  }
  const bool periodic[2] = {PeriodicX(scene.cell.periodicity), PeriodicY(scene.cell.periodicity)};
  // Relative slack on the reach absorbs the rounding of binning and of x_j + shift − x_i,
  // which scale with the magnitude of the coordinates.
  const double scale =
      std::max({hi.cwiseAbs().maxCoeff(), lo.cwiseAbs().maxCoeff(),
                periodic[0] ? scene.cell.size.x() : 0.0, periodic[1] ? scene.cell.size.y() : 0.0});
  const double min_width = reach * (1.0 + 1e-9) + 1e-12 * scale;
  // Cap the number of cells so that memory and the CSR pass stay linear in N.
  const double max_cells = 4.0 * static_cast<double>(particles.size()) + 16.0;
  std::array<Axis, 2> grid;
  for (int a = 0; a < 2; ++a) {
    grid[a] = periodic[a] ? MakeAxis(true, 0.0, scene.cell.size[a], min_width, max_cells)
                          : MakeAxis(false, lo[a], hi[a] - lo[a], min_width, max_cells);
  }
  // Coarsen the axis with the narrower cells, which keeps cells square-ish.
  while (static_cast<double>(grid[0].count) * grid[1].count > max_cells) {
    const bool shrink_x =
        grid[1].count == 1 || (grid[0].count > 1 && grid[0].width <= grid[1].width);
    Axis& axis = grid[shrink_x ? 0 : 1];
    SetCount(axis, std::max(1, axis.count / 2), min_width);
  }
  return grid;
}

// Counting sort of the particles into cells (CSR layout), in index order within a cell.
void BinParticles(const Scene& scene, const std::array<Axis, 2>& grid, Workspace& ws) {
  const int n = static_cast<int>(scene.particles.size());
  const int cells = grid[0].count * grid[1].count;
  ws.cell_of.resize(n);
  ws.wrap_of.resize(n);
  ws.entries.resize(n);
  ws.cell_start.assign(cells + 1, 0);
  for (int i = 0; i < n; ++i) {
    const Vec2& x = scene.particles[i].position;
    std::array<int, 2>& wrap = ws.wrap_of[i];
    const int cell = Bin(grid[0], x.x(), wrap[0]) + grid[0].count * Bin(grid[1], x.y(), wrap[1]);
    ws.cell_of[i] = cell;
    ++ws.cell_start[cell + 1];
  }
  for (int c = 0; c < cells; ++c) ws.cell_start[c + 1] += ws.cell_start[c];
  for (int i = 0; i < n; ++i) {
    const Particle& p = scene.particles[i];
    const int cell = ws.cell_of[i];
    ws.entries[ws.cell_start[cell]++] = {p.position.x(), p.position.y(), p.radius, i,
                                         cell,           ws.wrap_of[i],  p.fixed};
  }
  // Undo the post-increments: cell_start[c] now holds the start of cell c + 1.
  for (int c = cells; c > 0; --c) ws.cell_start[c] = ws.cell_start[c - 1];
  ws.cell_start[0] = 0;
}

// The neighbour cell `cell` (possibly −1 or count) of an axis, wrapped along a periodic
// axis with the period crossed in `shift`; −1 if it falls off an open axis.
int NeighbourCell(const Axis& axis, int cell, int& shift) {
  shift = 0;
  if (cell >= 0 && cell < axis.count) return cell;
  if (!axis.periodic) return -1;
  shift = cell < 0 ? -1 : 1;
  return cell - shift * axis.count;
}

// Appends the contacts of a with every j > i closer than the margin, in no particular order.
void AppendPairs(const Scene& scene, const std::array<Axis, 2>& grid, const Workspace& ws,
                 const Entry& a, double margin, std::vector<Contact>& out) {
  const int i = a.index;
  const int cx = a.cell % grid[0].count;
  const int cy = a.cell / grid[0].count;
  for (int dy = -1; dy <= 1; ++dy) {
    int sy = 0;
    const int ny = NeighbourCell(grid[1], cy + dy, sy);
    if (ny < 0) continue;
    for (int dx = -1; dx <= 1; ++dx) {
      int sx = 0;
      const int nx = NeighbourCell(grid[0], cx + dx, sx);
      if (nx < 0) continue;
      const int cell = nx + grid[0].count * ny;
      const int begin = ws.cell_start[cell];
      // A cell lists its particles in index order: walk down from the top while j > i.
      for (int k = ws.cell_start[cell + 1] - 1; k >= begin && ws.entries[k].index > i; --k) {
        const Entry& b = ws.entries[k];
        if (a.fixed && b.fixed) continue;
        // The binned positions are x − wrap ⊙ L, so the stored ones need these images.
        const std::array<int, 2> image = {sx + a.wrap[0] - b.wrap[0], sy + a.wrap[1] - b.wrap[1]};
        // The reference looks at images −1, 0, +1 only (never farther for wrapped input).
        if (std::abs(image[0]) > 1 || std::abs(image[1]) > 1) continue;
        // Cheap pre-test with a little slack so that it never rejects what MakeContact,
        // which decides with the reference's arithmetic, would accept.
        const double ex = (b.x + image[0] * scene.cell.size.x()) - a.x;
        const double ey = (b.y + image[1] * scene.cell.size.y()) - a.y;
        const double radii = a.radius + b.radius;
        const double bound = radii + margin + 1e-9 * (radii + std::abs(margin));
        if (bound <= 0.0 || ex * ex + ey * ey >= bound * bound) continue;
        Contact c = MakeContact(scene, i, b.index, image);
        if (c.gap < margin) out.push_back(c);
      }
    }
  }
}

// All disk pairs within the margin, into ws.pairs with the run of particle i at
// [run_begin[i], run_end[i]). Particles are visited in cell order rather than index order
// so that consecutive searches touch the same few cells: at large N this keeps the scan in
// cache, and the price is one copy of the (few) contacts when they are put in order.
void FindPairs(const Scene& scene, double margin, Workspace& ws) {
  const int n = static_cast<int>(scene.particles.size());
  ws.pairs.clear();
  ws.run_begin.assign(n, 0);
  ws.run_end.assign(n, 0);
  const double reach = 2.0 * MaxRadius(scene) + margin;
  // With a reach ≤ 0 no pair can qualify: every gap is ≥ −R_i − R_j ≥ −2 R_max ≥ margin.
  if (n < 2 || !(reach > 0.0)) return;
  const std::array<Axis, 2> grid = MakeGrid(scene, reach);
  BinParticles(scene, grid, ws);
  for (const Entry& a : ws.entries) {
    ws.run_begin[a.index] = static_cast<int>(ws.pairs.size());
    AppendPairs(scene, grid, ws, a, margin, ws.pairs);
    ws.run_end[a.index] = static_cast<int>(ws.pairs.size());
  }
}

}  // namespace

std::vector<Contact> DetectContacts(const Scene& scene, double margin) {
  contacts_internal::CheckMinimumImage(scene, margin);
  thread_local Workspace ws;
  FindPairs(scene, margin, ws);
  const int n = static_cast<int>(scene.particles.size());
  const int walls = static_cast<int>(scene.cell.walls.size());
  std::vector<Contact> contacts;
  contacts.reserve(ws.last_contact_count + ws.last_contact_count / 8 + 16);
  for (int i = 0; i < n; ++i) {
    const std::size_t first = contacts.size();
    // The runs are scattered in cell order: fetch ahead to hide the cache misses.
    if (i + 8 < n) __builtin_prefetch(ws.pairs.data() + ws.run_begin[i + 8]);
    contacts.insert(contacts.end(), ws.pairs.begin() + ws.run_begin[i],
                    ws.pairs.begin() + ws.run_end[i]);
    if (!scene.particles[i].fixed) {
      for (int w = 0; w < walls; ++w) {
        Contact c = MakeWallContact(scene, i, w);
        if (c.gap < margin) contacts.push_back(c);
      }
    }
    // Keys are unique and runs come by increasing i, so sorting each particle's run gives
    // the reference's global order.
    std::sort(contacts.begin() + first, contacts.end(), ContactKeyLess);
  }
  ws.last_contact_count = contacts.size();
  return contacts;
}

}  // namespace unjam
