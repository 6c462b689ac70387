#include "unjam/protocols/pressure_packing.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "random_placement.hpp"

namespace unjam {

double TimeUnit(const GasOptions& o) { return 1.0 / std::sqrt(o.pressure); }

Scene MakeGranularGas(const GasOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
  };
  require(o.particles >= 2, "--n must be at least 2");
  require(o.friction >= 0.0 && std::isfinite(o.friction), "--mu must be a finite number >= 0");
  require(o.pressure > 0.0 && std::isfinite(o.pressure), "--pressure must be positive");
  require(o.cell_mass > 0.0 && std::isfinite(o.cell_mass), "--cell-mass must be positive");
  require(o.initial_packing_fraction > 0.0 && o.initial_packing_fraction <= 0.5,
          "--initial-fraction must lie in (0, 0.5]");
  std::mt19937_64 rng(o.seed);
  const std::vector<double> radii = PolydisperseRadii(o.particles, rng);
  double area = 0.0;
  for (double r : radii) area += std::numbers::pi * r * r;
  // Minimum images need a cell of at least four largest diameters plus the margin.
  const double side = std::max(std::sqrt(area / o.initial_packing_fraction), 8.5);
  Scene scene;
  scene.seed = o.seed;
  scene.cell.size = Vec2(side, side);
  scene.cell.periodicity = Periodicity::kXY;
  scene.effects.friction = o.friction;
  scene.effects.pressure_bath = PressureBath{o.pressure, o.cell_mass, 0.0};
  PlaceWithoutOverlap(scene, radii, side, 0.0, side, true, rng);
  return scene;
}

}  // namespace unjam
