#include "unjam/protocols/gravity_pile.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace unjam {

namespace {

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

// A closed chain of touching fixed disks, stretched to the width (tiny gaps remain).
void AddBed(Scene& scene, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> radius(0.5, 1.0);
  std::vector<double> radii;
  double length = 0.0;
  for (;;) {
    const double r = radius(rng);
    if (length + 2.0 * r > scene.cell.size.x()) break;
    radii.push_back(r);
    length += 2.0 * r;
  }
  const double stretch = scene.cell.size.x() / length;
  double x = 0.0;
  for (double r : radii) {
    Particle p;
    p.radius = r;
    p.fixed = true;
    p.position = Vec2((x + r) * stretch, 1.0);
    scene.particles.push_back(p);
    x += 2.0 * r;
  }
}

// Random sequential addition above the bed, checked against a coarse grid of cells.
void AddLooseDisks(Scene& scene, const PileOptions& o, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> radius(0.5, 1.0);
  std::vector<double> radii(o.particles);
  double area = 0.0;
  for (double& r : radii) {
    r = radius(rng);
    area += std::numbers::pi * r * r;
  }
  const double bottom = 2.0 + 1e-3;  // above the tallest bed disk (top ≤ 2)
  const double height = area / (o.initial_packing_fraction * o.width);
  const int nx = std::max(1, static_cast<int>(o.width / 2.0));
  const int ny = std::max(1, static_cast<int>(height / 2.0) + 1);
  const double cw = o.width / nx;
  std::vector<std::vector<int>> grid(nx * ny);
  std::uniform_real_distribution<double> ux(0.0, o.width);
  for (double r : radii) {
    std::uniform_real_distribution<double> uy(bottom + r, bottom + std::max(height, 2.0 * r) - r + 1e-9);
    bool placed = false;
    for (int attempt = 0; attempt < 100000 && !placed; ++attempt) {
      const Vec2 x(ux(rng), uy(rng));
      const int cx = std::min(nx - 1, static_cast<int>(x.x() / cw));
      const int cy = std::clamp(static_cast<int>((x.y() - bottom) / 2.0), 0, ny - 1);
      placed = true;
      for (int dx = -1; dx <= 1 && placed; ++dx) {
        for (int dy = -1; dy <= 1 && placed; ++dy) {
          const int gx = (cx + dx + nx) % nx;
          const int gy = cy + dy;
          if (gy < 0 || gy >= ny) continue;
          for (int j : grid[gy * nx + gx]) {
            Vec2 d = scene.particles[j].position - x;
            d.x() -= o.width * std::round(d.x() / o.width);
            if (d.norm() < r + scene.particles[j].radius) { placed = false; break; }
          }
        }
      }
      if (!placed) continue;
      Particle p;
      p.radius = r;
      p.position = x;
      grid[cy * nx + cx].push_back(static_cast<int>(scene.particles.size()));
      scene.particles.push_back(p);
    }
    Require(placed, "could not place every disk: lower the initial packing fraction");
  }
  scene.cell.size.y() = bottom + height;
}

}  // namespace

Scene MakeLoosePile(const PileOptions& o) {
  Require(o.particles >= 1, "--n must be at least 1");
  Require(o.width >= 8.0, "--width must be at least 8 (four largest diameters)");
  Require(o.friction >= 0.0 && std::isfinite(o.friction), "--mu must be a finite number >= 0");
  Require(o.gravity > 0.0 && std::isfinite(o.gravity), "gravity must be positive");
  Require(o.initial_packing_fraction > 0.0 && o.initial_packing_fraction <= 0.5,
          "initial packing fraction must lie in (0, 0.5]");
  Scene scene;
  scene.seed = o.seed;
  scene.cell.size = Vec2(o.width, 1.0);
  scene.cell.periodicity = Periodicity::kX;
  scene.effects.gravity = Vec2(0.0, -o.gravity);
  scene.effects.friction = o.friction;
  std::mt19937_64 rng(o.seed);
  AddBed(scene, rng);
  AddLooseDisks(scene, o, rng);
  return scene;
}

SettleReport Settle(Simulation& sim, const SettleOptions& o) {
  SettleReport report;
  const Scene& scene = sim.scene();
  const double g = scene.effects.gravity ? scene.effects.gravity->norm() : 0.0;
  const double threshold = o.speed_threshold * std::sqrt(std::max(g, 1e-300) * MaxRadius(scene));
  int calm = 0;
  while (report.steps < o.max_steps && calm < o.window) {
    const StepReport step = sim.Step();
    ++report.steps;
    if (!step.solve.converged()) ++report.unconverged_steps;
    report.max_speed = 0.0;
    for (const Particle& p : sim.scene().particles) {
      if (!p.fixed) report.max_speed = std::max(report.max_speed, p.velocity.norm() + p.radius * std::abs(p.spin));
    }
    calm = report.max_speed < threshold ? calm + 1 : 0;
    if (o.progress && o.progress_interval > 0 && report.steps % o.progress_interval == 0) {
      o.progress(report.steps, step.kinetic_energy);
    }
  }
  report.settled = calm >= o.window;
  return report;
}

}  // namespace unjam
