#include "random_placement.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace unjam {

std::vector<double> PolydisperseRadii(int count, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> radius(0.5, 1.0);
  std::vector<double> radii(count);
  for (double& r : radii) r = radius(rng);
  return radii;
}

namespace {

// A coarse grid of cells of side ≥ 2 (the largest diameter) over the placement region.
class PlacementGrid {
 public:
  PlacementGrid(double width, double bottom, double top, bool periodic_y)
      : width_(width), bottom_(bottom), height_(top - bottom), periodic_y_(periodic_y),
        nx_(std::max(1, static_cast<int>(width / 2.0))),
        ny_(std::max(1, static_cast<int>(height_ / 2.0))), cells_(nx_ * ny_) {}

  bool Free(const Scene& scene, const Vec2& x, double r) const {
    const auto [cx, cy] = CellOf(x);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        int gy = cy + dy;
        if (periodic_y_) gy = (gy + ny_) % ny_;
        if (gy < 0 || gy >= ny_) continue;
        for (int j : cells_[gy * nx_ + (cx + dx + nx_) % nx_]) {
          Vec2 d = scene.particles[j].position - x;
          d.x() -= width_ * std::round(d.x() / width_);
          if (periodic_y_) d.y() -= height_ * std::round(d.y() / height_);
          if (d.norm() < r + scene.particles[j].radius) return false;
        }
      }
    }
    return true;
  }

  void Add(const Vec2& x, int index) {
    const auto [cx, cy] = CellOf(x);
    cells_[cy * nx_ + cx].push_back(index);
  }

 private:
  std::pair<int, int> CellOf(const Vec2& x) const {
    const int cx = std::clamp(static_cast<int>(x.x() / width_ * nx_), 0, nx_ - 1);
    const int cy = std::clamp(static_cast<int>((x.y() - bottom_) / height_ * ny_), 0, ny_ - 1);
    return {cx, cy};
  }

  double width_, bottom_, height_;
  bool periodic_y_;
  int nx_, ny_;
  std::vector<std::vector<int>> cells_;
};

}  // namespace

void PlaceWithoutOverlap(Scene& scene, const std::vector<double>& radii, double width,
                         double bottom, double top, bool periodic_y, std::mt19937_64& rng) {
  PlacementGrid grid(width, bottom, top, periodic_y);
  std::uniform_real_distribution<double> ux(0.0, width);
  for (double r : radii) {
    // Without periodicity in y the whole disk stays inside [bottom, top).
    const double lo = periodic_y ? bottom : bottom + r;
    const double hi = periodic_y ? top : std::max(lo, top - r);
    std::uniform_real_distribution<double> uy(lo, hi);
    bool placed = false;
    for (int attempt = 0; attempt < 100000 && !placed; ++attempt) {
      const Vec2 x(ux(rng), uy(rng));
      if (!grid.Free(scene, x, r)) continue;
      Particle p;
      p.radius = r;
      p.position = x;
      grid.Add(x, static_cast<int>(scene.particles.size()));
      scene.particles.push_back(p);
      placed = true;
    }
    if (!placed)
      throw std::invalid_argument("could not place every disk: lower the initial packing fraction");
  }
}

}  // namespace unjam
