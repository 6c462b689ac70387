// Homogeneous packings at constant external pressure in a fully periodic cell.
//
// Start: a dilute granular gas — N disks, radii uniform in [0.5, 1], placed at random
// without overlap and at rest in a square cell, periodic in x and y, no walls, no gravity.
// The pressure bath (P_ext, cell mass M_λ) then compresses the cell, whose size is a
// degree of freedom coupled inside every contact solve (docs/method.md), until jammed
// (RelaxToStatic).
#pragma once

#include <cstdint>

#include "unjam/scene/scene.hpp"

namespace unjam {

struct GasOptions {
  int particles = 500;
  double friction = 0.5;
  double pressure = 1.0;
  double cell_mass = 100.0;  // M_λ, density × length²
  double initial_packing_fraction = 0.3;
  std::uint64_t seed = 1;
};

// T₀ = R_max √(ρ/P_ext) of a gas (R_max = 1, ρ = 1): the unit of its time step (relax.hpp).
double TimeUnit(const GasOptions& options);

// Throws std::invalid_argument naming the option when a value is out of range.
Scene MakeGranularGas(const GasOptions& options);

}  // namespace unjam
