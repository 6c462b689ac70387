// Geometry of one contact: normal, gap, branch vectors. Shared by the broad phase and the
// brute-force reference so that both produce bit-identical contacts.
#include <cmath>

#include "unjam/contacts/contact.hpp"

namespace unjam {

Contact MakeContact(const Scene& scene, int i, int j, std::array<int, 2> image) {
  const Particle& a = scene.particles[i];
  const Particle& b = scene.particles[j];
  const Vec2 shift(image[0] * scene.cell.size.x(), image[1] * scene.cell.size.y());
  Contact c;
  c.i = i;
  c.j = j;
  c.image = image;
  c.center_to_center = (b.position + shift) - a.position;
  const double distance = c.center_to_center.norm();
  // Coincident centres have no normal; pick one so that the result stays finite.
  c.normal = distance > 0.0 ? Vec2(c.center_to_center / distance) : Vec2(1.0, 0.0);
  c.gap = distance - a.radius - b.radius;
  c.branch_i = a.radius * c.normal;
  c.branch_j = -b.radius * c.normal;
  return c;
}

Contact MakeWallContact(const Scene& scene, int i, int wall) {
  const Particle& a = scene.particles[i];
  const Wall& w = scene.cell.walls[wall];
  Contact c;
  c.i = i;
  c.j = WallIndexToJ(wall);
  c.normal = -w.normal;
  const double distance = (a.position - w.point).dot(w.normal);
  c.gap = distance - a.radius;
  c.branch_i = a.radius * c.normal;
  c.branch_j = Vec2::Zero();
  c.center_to_center = distance * c.normal;
  return c;
}

}  // namespace unjam
