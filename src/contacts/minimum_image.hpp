// Internal to src/contacts: the guard shared by the cell list and the brute-force
// reference, so that both reject exactly the same scenes.
#pragma once

#include <sstream>
#include <stdexcept>

#include "unjam/scene/scene.hpp"

namespace unjam::contacts_internal {

// Two images of a disk are a cell length L apart, so when L ≥ 2 (2 R_max + margin) at
// most one image of each pair can have a gap below the margin and "the" contact of a pair
// is well defined (minimum image). Below that the answer would depend on which images one
// looks at, hence the error.
inline void CheckMinimumImage(const Scene& scene, double margin) {
  const double reach = 2.0 * MaxRadius(scene) + margin;
  const Periodicity p = scene.cell.periodicity;
  for (int axis = 0; axis < 2; ++axis) {
    const bool periodic = axis == 0 ? PeriodicX(p) : PeriodicY(p);
    const double length = scene.cell.size[axis];
    if (periodic && length < 2.0 * reach) {
      std::ostringstream message;
      message << "contact detection: periodic cell length " << length << " along "
              << (axis == 0 ? 'x' : 'y') << " is below 2 (2 R_max + margin) = " << 2.0 * reach
              << "; the minimum image is ambiguous";
      throw std::invalid_argument(message.str());
    }
  }
}

}  // namespace unjam::contacts_internal
