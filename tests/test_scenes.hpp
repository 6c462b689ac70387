// Small analytic scenes shared by the tests.
#pragma once

#include <cmath>
#include <numbers>
#include <string>

#include "unjam/io/packing_file.hpp"
#include "unjam/scene/scene.hpp"

namespace unjam::testing {

inline Particle Disk(double x, double y, double r, bool fixed = false) {
  Particle p;
  p.position = Vec2(x, y);
  p.radius = r;
  p.fixed = fixed;
  return p;
}

inline Wall Floor(double height = 0.0) { return Wall{Vec2(0.0, height), Vec2(0.0, 1.0)}; }

// Disk 2 (radius 1) resting in a V-groove of two fixed disks 0 and 1 (radius 1) at x = ∓a
// (0 < a < 2), touching both at height h = √(4 − a²): each contact normal makes the angle
// asin(a/2) with the vertical. Gravity −1, friction μ, no periodicity.
inline Scene VGroove(double a, double mu) {
  Scene s;
  s.cell.size = Vec2(20.0, 20.0);
  s.effects.gravity = Vec2(0.0, -1.0);
  s.effects.friction = mu;
  s.particles = {Disk(-a, 0.0, 1.0, true), Disk(a, 0.0, 1.0, true),
                 Disk(0.0, std::sqrt(4.0 - a * a), 1.0)};
  return s;
}

// k equal disks of radius r stacked on a floor, touching (gap 0).
inline Scene Stack(int k, double r, double g, double mu) {
  Scene s;
  s.cell.size = Vec2(10.0, 2.0 * r * k + 1.0);
  s.cell.walls.push_back(Floor());
  s.effects.gravity = Vec2(0.0, -g);
  s.effects.friction = mu;
  for (int i = 0; i < k; ++i) s.particles.push_back(Disk(0.0, r + 2.0 * r * i, r));
  return s;
}

// A periodic triangular lattice of equal touching disks: nx per row, ny rows (even).
inline Scene TriangularLattice(int nx, int ny, double r) {
  Scene s;
  const double dy = std::sqrt(3.0) * r;
  s.cell.size = Vec2(2.0 * r * nx, dy * ny);
  s.cell.periodicity = Periodicity::kXY;
  for (int row = 0; row < ny; ++row) {
    for (int col = 0; col < nx; ++col) {
      const double x = 2.0 * r * col + (row % 2 == 1 ? r : 0.0) + 0.5 * r;
      s.particles.push_back(Disk(x, dy * (row + 0.5), r));
    }
  }
  return s;
}

// A case of the hard-case catalogue, problems/hard/NAME.unjam (problems/hard/README.md).
inline Scene HardCase(const std::string& name) {
  return ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/hard/" + name + ".unjam");
}

// The analytic contact force (f_n, |f_t|) of problems/hard/heavy-on-light.unjam
// (problems/hard/README.md): a disk of density 1e6 on two light ones, on a floor.
struct NormalAndTangential {
  double normal, tangential;
};
inline NormalAndTangential HeavyOnLightForce(bool floor_contact) {
  const double heavy = 1e6 * std::numbers::pi / 4.0;
  if (floor_contact) return {heavy / 2.0 + std::numbers::pi / 4.0, heavy / 6.0};
  return {heavy / 2.0, heavy / 6.0};
}

}  // namespace unjam::testing
