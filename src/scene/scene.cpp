#include "unjam/scene/scene.hpp"

#include <algorithm>
#include <cmath>

namespace unjam {

double MaxRadius(const Scene& scene) {
  double r = 0.0;
  for (const Particle& p : scene.particles) r = std::max(r, p.radius);
  return r;
}

std::vector<char> MovableParticles(const Scene& scene) {
  std::vector<char> movable(scene.particles.size(), 1);
  for (std::size_t i = 0; i < scene.particles.size(); ++i) movable[i] = !scene.particles[i].fixed;
  for (const PrescribedMotion& m : scene.effects.prescribed_motion) movable[m.particle] = 0;
  return movable;
}

double PackingFraction(const Scene& scene) {
  if (scene.particles.empty()) return 0.0;
  double area = 0.0;
  double bottom = scene.particles[0].position.y() - scene.particles[0].radius;
  double top = scene.particles[0].position.y() + scene.particles[0].radius;
  for (const Particle& p : scene.particles) {
    area += std::numbers::pi * p.radius * p.radius;
    bottom = std::min(bottom, p.position.y() - p.radius);
    top = std::max(top, p.position.y() + p.radius);
  }
  const double height = PeriodicY(scene.cell.periodicity) ? scene.cell.size.y() : top - bottom;
  return area / (scene.cell.size.x() * height);
}

namespace {
double WrapCoordinate(double x, double length) {
  double w = x - length * std::floor(x / length);
  // floor can round w up to exactly `length` for tiny negative x.
  return w >= length ? 0.0 : w;
}
}  // namespace

void WrapPositions(Scene& scene) {
  const Periodicity p = scene.cell.periodicity;
  for (Particle& particle : scene.particles) {
    if (PeriodicX(p))
      particle.position.x() = WrapCoordinate(particle.position.x(), scene.cell.size.x());
    if (PeriodicY(p))
      particle.position.y() = WrapCoordinate(particle.position.y(), scene.cell.size.y());
  }
}

double CellInertia(const Scene& scene) {
  const double volume = scene.cell.size.x() * scene.cell.size.y();
  return scene.effects.pressure_bath->cell_mass * kDimension * volume;
}

double CarryingThreshold(const std::vector<double>& normal_forces) {
  double sum = 0.0;
  int count = 0;
  for (double f : normal_forces) {
    if (!(f > 0.0)) continue;
    sum += f;
    ++count;
  }
  return count > 0 ? 1e-10 * sum / count : 0.0;
}

double CarryingThreshold(const std::vector<ContactForce>& forces) {
  std::vector<double> normals;
  for (const ContactForce& f : forces) normals.push_back(f.normal);
  return CarryingThreshold(normals);
}

std::vector<ContactForce> ForceCarryingPairs(const Scene& scene) {
  const double threshold = CarryingThreshold(scene.forces);
  std::vector<ContactForce> out;
  for (const ContactForce& f : scene.forces) {
    if (!(f.normal > threshold) || IsWallIndex(f.j)) continue;
    if (scene.particles[f.i].fixed && scene.particles[f.j].fixed) continue;
    out.push_back(f);
  }
  return out;
}

void BringToRest(Scene& scene) {
  for (Particle& p : scene.particles) {
    p.velocity = Vec2::Zero();
    p.spin = 0.0;
  }
  if (scene.effects.pressure_bath) scene.effects.pressure_bath->strain_rate = 0.0;
}

Vec2 MinimumImage(const Cell& cell, Vec2 v) {
  if (PeriodicX(cell.periodicity)) v.x() -= cell.size.x() * std::round(v.x() / cell.size.x());
  if (PeriodicY(cell.periodicity)) v.y() -= cell.size.y() * std::round(v.y() / cell.size.y());
  return v;
}

}  // namespace unjam
