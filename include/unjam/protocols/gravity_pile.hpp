// Piles settled under gravity on a rough bed, periodic in x.
//
// The bed is a closed chain of fixed disks with random radii in [0.5, 1] whose centres lie
// on y = 1; free disks (radii uniform in [0.5, 1]) start at rest at random non-overlapping
// places above it, at a given packing fraction, and fall under gravity until static
// (RelaxToStatic, relax.hpp).
#pragma once

#include <cstdint>

#include "unjam/scene/scene.hpp"

namespace unjam {

struct PileOptions {
  int particles = 200;
  double width = 20.0;
  double friction = 0.5;
  double gravity = 1.0;
  double initial_packing_fraction = 0.35;
  std::uint64_t seed = 1;
};

// T₀ = √(R_max/g) of a pile (R_max = 1): the unit of its time step (relax.hpp).
double TimeUnit(const PileOptions& options);

// Throws std::invalid_argument naming the option when a value is out of range.
Scene MakeLoosePile(const PileOptions& options);

}  // namespace unjam
