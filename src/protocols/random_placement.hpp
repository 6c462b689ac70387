// Random sequential placement of disks without overlap (the dilute starting states).
#pragma once

#include <random>
#include <vector>

#include "unjam/scene/scene.hpp"

namespace unjam {

// Radii uniform in [0.5, 1] (the unit of length is the largest radius).
std::vector<double> PolydisperseRadii(int count, std::mt19937_64& rng);

// Appends disks with the given radii at random positions in [0, width) × [bottom, top),
// x periodic with period `width`, y periodic with period top − bottom if `periodic_y`,
// none overlapping another appended disk. Throws std::invalid_argument if a disk finds no
// place in 100000 attempts.
void PlaceWithoutOverlap(Scene& scene, const std::vector<double>& radii, double width,
                         double bottom, double top, bool periodic_y, std::mt19937_64& rng);

}  // namespace unjam
