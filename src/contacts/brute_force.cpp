// O(N²) contact detection: the reference that the cell list is tested against.
#include <algorithm>

#include "minimum_image.hpp"
#include "unjam/contacts/contact.hpp"

namespace unjam {

namespace {
// Images of j to examine along one axis: all three neighbours when periodic, else none.
std::vector<int> ImageRange(bool periodic) {
  return periodic ? std::vector<int>{-1, 0, 1} : std::vector<int>{0};
}
}  // namespace

std::vector<Contact> DetectContactsBruteForce(const Scene& scene, double margin) {
  contacts_internal::CheckMinimumImage(scene, margin);
  std::vector<Contact> contacts;
  const int n = static_cast<int>(scene.particles.size());
  const auto xs = ImageRange(PeriodicX(scene.cell.periodicity));
  const auto ys = ImageRange(PeriodicY(scene.cell.periodicity));
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (scene.particles[i].fixed && scene.particles[j].fixed) continue;
      for (int sx : xs) {
        for (int sy : ys) {
          Contact c = MakeContact(scene, i, j, {sx, sy});
          if (c.gap < margin) contacts.push_back(c);
        }
      }
    }
    if (scene.particles[i].fixed) continue;
    for (int w = 0; w < static_cast<int>(scene.cell.walls.size()); ++w) {
      Contact c = MakeWallContact(scene, i, w);
      if (c.gap < margin) contacts.push_back(c);
    }
  }
  std::sort(contacts.begin(), contacts.end(), ContactKeyLess);
  return contacts;
}

}  // namespace unjam
