// Piles settled under gravity on a rough bed, periodic in x.
//
// The bed is a closed chain of fixed disks with random radii in [0.5, 1] whose centres lie
// on y = 1; free disks (radii uniform in [0.5, 1]) start at rest at random non-overlapping
// places above it, at a given packing fraction, and fall under gravity until static.
#pragma once

#include <cstdint>
#include <functional>

#include "unjam/scene/scene.hpp"
#include "unjam/stepping/simulation.hpp"

namespace unjam {

struct PileOptions {
  int particles = 200;
  double width = 20.0;
  double friction = 0.5;
  double gravity = 1.0;
  double initial_packing_fraction = 0.35;
  std::uint64_t seed = 1;
};

// Throws std::invalid_argument naming the option when a value is out of range.
Scene MakeLoosePile(const PileOptions& options);

struct SettleOptions {
  StepOptions step;
  int max_steps = 200000;
  // Static when the largest particle speed stays below speed_threshold·√(g·R_max) for
  // `window` consecutive steps.
  double speed_threshold = 1e-6;
  int window = 50;
  // Called every `progress_interval` steps with (step, kinetic energy), 0 = never.
  int progress_interval = 0;
  std::function<void(int, double)> progress;
};

struct SettleReport {
  bool settled = false;
  int steps = 0;
  int unconverged_steps = 0;   // steps whose contact solve hit its iteration limit
  double max_speed = 0.0;      // at the end
};

SettleReport Settle(Simulation& simulation, const SettleOptions& options);

}  // namespace unjam
