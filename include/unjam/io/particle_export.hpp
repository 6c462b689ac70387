// Particles with displacement vectors and contact forces, in files that visualisation
// tools open directly: legacy VTK polydata (ParaView: vertices = disk centres, lines =
// force-carrying contacts) and extended XYZ (OVITO: one row per disk).
#pragma once

#include <filesystem>
#include <vector>

#include "unjam/scene/scene.hpp"

namespace unjam {

struct ParticleField {
  std::vector<Vec2> displacement;          // per particle (may be empty: written as zero)
  std::vector<ContactForce> forces;        // contact forces to draw (may be empty)
  std::vector<ContactForce> force_change;  // per contact ΔF (same keys; may be empty)
};

// ASCII legacy VTK ("# vtk DataFile Version 3.0", DATASET POLYDATA). Points: disk centres
// (z = 0), then for every contact line the image point of j (x_j + image shift; the
// contact point for a wall) so that lines across the periodic boundary are drawn whole.
// VERTICES: one per disk. LINES: one per entry of `forces`. POINT_DATA for the disk
// points: radius, fixed (0/1), displacement (vector, z = 0); extra points get zero.
// CELL_DATA: for vertices 0, for lines normal_force, tangential_force, force_change
// (normal ΔF from `force_change` matched by key, 0 if absent).
// Written atomically (WriteFileAtomically): no partial file on failure.
void WriteVtk(const Scene& scene, const ParticleField& field, const std::filesystem::path& path);

// Extended XYZ: line 1 the particle count; line 2 the one-line header
//   Lattice="Lx 0 0 0 Ly 0 0 0 1" Properties=id:I:1:pos:R:3:radius:R:1:fixed:I:1:displacement:R:3
//   pbc="T T F"
// (pbc from the cell's periodicity); then one row per disk. Written atomically.
void WriteExtendedXyz(const Scene& scene, const ParticleField& field,
                      const std::filesystem::path& path);

}  // namespace unjam
