#include "unjam/analysis/hanging_grains.hpp"

namespace unjam {

std::vector<int> HangingGrains(const Scene& scene, const std::vector<Contact>& contacts) {
  if (!scene.effects.gravity || scene.effects.gravity->norm() == 0.0) return {};
  const Vec2 g = *scene.effects.gravity;
  const std::size_t n = scene.particles.size();
  std::vector<int> contacts_of(n, 0);
  std::vector<char> held_from_below(n, 0);  // a contact a fall would close (n·g ≥ 0)
  auto visit = [&](int grain, const Vec2& to_neighbour) {
    ++contacts_of[grain];
    if (to_neighbour.dot(g) >= 0.0) held_from_below[grain] = 1;
  };
  for (const Contact& c : contacts) {
    visit(c.i, c.normal);
    if (!c.WithWall()) visit(c.j, -c.normal);
  }
  std::vector<int> hanging;
  for (std::size_t k = 0; k < n; ++k) {
    if (!scene.particles[k].fixed && contacts_of[k] > 0 && !held_from_below[k])
      hanging.push_back(static_cast<int>(k));
  }
  return hanging;
}

}  // namespace unjam
