#include "unjam/protocols/gravity_pile.hpp"

#include "random_placement.hpp"

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

// Random sequential addition above the bed (top of the bed ≤ 2).
void AddLooseDisks(Scene& scene, const PileOptions& o, std::mt19937_64& rng) {
  const std::vector<double> radii = PolydisperseRadii(o.particles, rng);
  double area = 0.0;
  for (double r : radii) area += std::numbers::pi * r * r;
  const double bottom = 2.0 + 1e-3;
  const double height = std::max(area / (o.initial_packing_fraction * o.width), 2.0);
  PlaceWithoutOverlap(scene, radii, o.width, bottom, bottom + height, false, rng);
  scene.cell.size.y() = bottom + height;
}

}  // namespace

double TimeUnit(const PileOptions& o) { return std::sqrt(1.0 / o.gravity); }

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

}  // namespace unjam
