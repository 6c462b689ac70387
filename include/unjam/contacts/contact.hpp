// Contact geometry between two disks, or a disk and a wall.
//
// Conventions (used everywhere in unjam): the normal n points from i to j, the tangent is
// t = Perp(n). The gap is |x_j + shift − x_i| − R_i − R_j (negative = overlap). For a wall,
// j = WallIndexToJ(w) and n = −wall normal.
#pragma once

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "unjam/scene/scene.hpp"

namespace unjam {

struct Contact {
  int i = -1;
  int j = -1;                         // particle index, or a wall (IsWallIndex(j))
  std::array<int, 2> image = {0, 0};  // j is taken at x_j + image ⊙ cell size
  Vec2 normal = Vec2(1.0, 0.0);       // unit, from i to j
  double gap = 0.0;
  Vec2 branch_i = Vec2::Zero();  // centre of i to the contact point (= R_i n)
  Vec2 branch_j = Vec2::Zero();  // centre of j to the contact point (= −R_j n; zero for a wall)
  Vec2 center_to_center =
      Vec2::Zero();  // x_j + shift − x_i (minimum image); for a wall, (R_i + gap) n

  bool WithWall() const { return IsWallIndex(j); }
};

// Contacts ordered by (i, j, image) so that successive steps can be merged in linear time.
inline bool ContactKeyLess(const Contact& a, const Contact& b) {
  if (a.i != b.i) return a.i < b.i;
  if (a.j != b.j) return a.j < b.j;
  return a.image < b.image;
}
inline bool SameContactKey(const Contact& a, const Contact& b) {
  return a.i == b.i && a.j == b.j && a.image == b.image;
}
inline bool ForceKeyLess(const ContactForce& a, const ContactForce& b) {
  if (a.i != b.i) return a.i < b.i;
  if (a.j != b.j) return a.j < b.j;
  return a.image < b.image;
}

// Index of the contact (i, j, image) in `sorted` (ordered by ContactKeyLess, as detection
// returns them), or −1.
inline int FindContact(const std::vector<Contact>& sorted, int i, int j,
                       const std::array<int, 2>& image) {
  Contact probe;
  probe.i = i;
  probe.j = j;
  probe.image = image;
  auto it = std::lower_bound(sorted.begin(), sorted.end(), probe, ContactKeyLess);
  return it == sorted.end() || !SameContactKey(*it, probe) ? -1
                                                           : static_cast<int>(it - sorted.begin());
}

// Forces (stored, saved, or a reference) looked up by the key of a contact: sorted once,
// each lookup O(log n).
class ForcesByContact {
 public:
  explicit ForcesByContact(std::vector<ContactForce> forces) : sorted_(std::move(forces)) {
    std::sort(sorted_.begin(), sorted_.end(), ForceKeyLess);
  }
  // The force of contact c, or nullptr if none is stored.
  const ContactForce* Find(const Contact& c) const {
    const ContactForce probe{c.i, c.j, c.image, 0.0, 0.0};
    auto it = std::lower_bound(sorted_.begin(), sorted_.end(), probe, ForceKeyLess);
    return it == sorted_.end() || ForceKeyLess(probe, *it) ? nullptr : &*it;
  }

 private:
  std::vector<ContactForce> sorted_;
};

// All pairs (and disk–wall pairs) whose gap is below `margin`, sorted by ContactKeyLess,
// each pair once with i < j for disk pairs. Pairs of two fixed disks are skipped.
// Cost linear in the number of particles (cell list with periodic images).
// Throws std::invalid_argument if a periodic cell is too small for minimum images
// (cell length below 2 (2 R_max + margin)).
std::vector<Contact> DetectContacts(const Scene& scene, double margin);

// The O(N²) reference used by tests: same output, every pair examined.
std::vector<Contact> DetectContactsBruteForce(const Scene& scene, double margin);

// Geometry of the pair (i, j at the given image), whatever its gap.
Contact MakeContact(const Scene& scene, int i, int j, std::array<int, 2> image);
Contact MakeWallContact(const Scene& scene, int i, int wall);

}  // namespace unjam
