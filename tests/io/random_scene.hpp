// Random valid scenes for the `.unjam` reader and writer tests: every double field takes
// arbitrary finite bit patterns where the format allows it (subnormals, -0.0, 1e-300,
// 0.1 + 0.2, ±DBL_MAX), while positions and radii stay valid (no overlap, inside periodic
// cells, walls keep every disk inside).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <tuple>

#include "unjam/scene/scene.hpp"

namespace unjam::testing {

inline double SpecialDouble(std::mt19937_64& rng) {
  static const double kSpecial[] = {0.0,
                                    -0.0,
                                    5e-324,
                                    -5e-324,
                                    2.2250738585072014e-308,
                                    1e-300,
                                    -1e-300,
                                    0.1 + 0.2,
                                    1.0 / 3.0,
                                    std::numeric_limits<double>::max(),
                                    -std::numeric_limits<double>::max(),
                                    123456789.123456789,
                                    1e300};
  return kSpecial[rng() % std::size(kSpecial)];
}

// Finite doubles with uniformly random bits (so all exponents, subnormals included), and
// the special values a quarter of the time.
inline double AnyFiniteDouble(std::mt19937_64& rng) {
  if (rng() % 4 == 0) return SpecialDouble(rng);
  for (;;) {
    const double v = std::bit_cast<double>(static_cast<std::uint64_t>(rng()));
    if (std::isfinite(v)) return v;
  }
}

inline double AnyPositiveDouble(std::mt19937_64& rng) {
  for (;;) {
    const double v = std::abs(AnyFiniteDouble(rng));
    if (v > 0.0) return v;
  }
}

// Radius in (0, 0.3] or one of the awkward values of that range.
inline double AnyRadius(std::mt19937_64& rng) {
  static const double kSpecial[] = {5e-324, 1e-300, 0.1 + 0.2, 0.3, 2.2250738585072014e-308};
  if (rng() % 5 == 0) return kSpecial[rng() % std::size(kSpecial)];
  return std::uniform_real_distribution<double>(1e-9, 0.3)(rng);
}

// Effects and forces that refer to the particles and walls already in `scene`.
inline void AddRandomEffectsAndForces(Scene& scene, bool walls, std::mt19937_64& rng) {
  const int n = static_cast<int>(scene.particles.size());
  if (rng() % 2) scene.effects.gravity = Vec2(AnyFiniteDouble(rng), AnyFiniteDouble(rng));
  if (rng() % 2) scene.effects.friction = AnyPositiveDouble(rng);
  if (scene.cell.periodicity == Periodicity::kXY && rng() % 2) {
    scene.effects.pressure_bath =
        PressureBath{AnyFiniteDouble(rng), AnyPositiveDouble(rng), AnyFiniteDouble(rng)};
  }
  for (int k = 0; k < n; k += 1 + static_cast<int>(rng() % 4)) {
    scene.effects.prescribed_motion.push_back(
        {k, Vec2(AnyFiniteDouble(rng), AnyFiniteDouble(rng)), AnyFiniteDouble(rng)});
  }
  const int image_x = PeriodicX(scene.cell.periodicity) ? 1 : 0;
  const int image_y = PeriodicY(scene.cell.periodicity) ? -1 : 0;
  for (int k = 0; n >= 2 && k < 3; ++k) {
    const int i = static_cast<int>(rng() % n);
    scene.effects.prescribed_gaps.push_back(
        {i, (i + 1) % n, {image_x, image_y}, AnyFiniteDouble(rng)});
  }
  // One force line per contact ((i, j, m) and (j, i, -m) are one), none pulling: the reader
  // refuses a second line and a negative normal force.
  std::set<std::tuple<int, int, int, int>> contacts;
  const int forces = n >= 2 ? static_cast<int>(rng() % 8) : 0;
  for (int k = 0; k < forces; ++k) {
    const int i = static_cast<int>(rng() % n);
    ContactForce f;
    f.i = i;
    const bool wall = walls && rng() % 3 == 0;
    f.j = wall ? WallIndexToJ(static_cast<int>(rng() % scene.cell.walls.size())) : (i + 1) % n;
    f.image = wall ? std::array<int, 2>{0, 0} : std::array<int, 2>{image_x, 0};
    f.normal = std::abs(AnyFiniteDouble(rng));
    f.tangential = AnyFiniteDouble(rng);
    const bool first = wall || f.i < f.j;
    const auto key = first ? std::make_tuple(f.i, f.j, f.image[0], f.image[1])
                           : std::make_tuple(f.j, f.i, -f.image[0], -f.image[1]);
    if (contacts.insert(key).second) scene.forces.push_back(f);
  }
}

inline Scene RandomScene(std::mt19937_64& rng) {
  Scene scene;
  const int cols = 2 + static_cast<int>(rng() % 6);
  const int rows = 2 + static_cast<int>(rng() % 5);
  const int mode = static_cast<int>(rng() % 3);
  scene.cell.periodicity = mode == 0   ? Periodicity::kNone
                           : mode == 1 ? Periodicity::kX
                                       : Periodicity::kXY;
  // Disks sit near the centres of unit squares: radius ≤ 0.30000000000000004 and jitter
  // ≤ 0.05 keep every gap positive, also across periodic boundaries.
  scene.cell.size = Vec2(cols + std::uniform_real_distribution<double>(0.0, 0.5)(rng),
                         rows + std::uniform_real_distribution<double>(0.0, 0.5)(rng));
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (rng() % 4 == 0) continue;
      Particle p;
      p.position = Vec2(c + 0.5 + jitter(rng), r + 0.5 + jitter(rng));
      p.angle = AnyFiniteDouble(rng);
      p.velocity = Vec2(AnyFiniteDouble(rng), AnyFiniteDouble(rng));
      p.spin = AnyFiniteDouble(rng);
      p.radius = AnyRadius(rng);
      p.density = AnyPositiveDouble(rng);
      p.fixed = rng() % 5 == 0;
      scene.particles.push_back(p);
    }
  }
  if (!scene.particles.empty() && rng() % 2 == 0) {
    scene.particles[0].position = Vec2(-0.0, 0.0);  // -0.0 is inside [0, L)
    scene.particles[0].radius = 0.1;
  }
  const bool walls = rng() % 2 == 0;
  if (walls) {
    // Far enough from the centre on the outside of every disk, whatever the direction.
    const Vec2 centre = 0.5 * scene.cell.size;
    const int count = 1 + static_cast<int>(rng() % 3);
    for (int w = 0; w < count; ++w) {
      const double theta = std::uniform_real_distribution<double>(0.0, 2.0 * std::numbers::pi)(rng);
      Wall wall;
      wall.normal = Vec2(std::cos(theta), std::sin(theta));
      wall.point = centre - (cols + rows + 1.0) * wall.normal;
      scene.cell.walls.push_back(wall);
    }
  } else if (scene.cell.periodicity == Periodicity::kNone) {
    // Without walls or periodicity x is unconstrained: arbitrary doubles, each disk on its
    // own row below the grid so that none can overlap.
    for (int k = 0; k < 3; ++k) {
      Particle p;
      p.position = Vec2(AnyFiniteDouble(rng), -2.0 - 2.0 * k);
      p.radius = AnyRadius(rng);
      p.density = AnyPositiveDouble(rng);
      scene.particles.push_back(p);
    }
  }
  AddRandomEffectsAndForces(scene, walls, rng);
  scene.seed = rng();
  const int length = static_cast<int>(rng() % 40);
  for (int k = 0; k < length; ++k) scene.provenance += static_cast<char>(rng() % 256);
  return scene;
}

}  // namespace unjam::testing
