// Contact closure: move particles by the smallest displacement that closes chosen contacts
// exactly (gap 0 to round-off).
//
// Contact dynamics closes the gap of a force-carrying contact only to the accuracy of the
// step's solve (the position-level Signorini condition g + Δt u_n ≥ 0 holds to the
// residual). Before a packing is declared static, the contacts of its certified force
// network (indeterminacy/admissible_forces.hpp) are closed exactly, so that the saved
// state has every carrying contact at gap 0 and no overlap: a later perturbation of 1e-9
// is then far above the geometric noise.
//
// Linearised gaps: g_k(x + Δx) ≈ g_k + n_k·(Δx_j − Δx_i) (+ ε l_k·n_k under a pressure bath,
// ε the relative change of the cell size, which rescales all positions with the cell).
// The correction of smallest norm, Δ = Gᵀ (G Gᵀ)⁻¹ (−g), is applied and repeated (gaps are
// not linear in x), with the sparse Cholesky of CHOLMOD. Fixed particles and particles with
// prescribed motion do not move.
#pragma once

#include <array>
#include <vector>

#include "unjam/scene/scene.hpp"

namespace unjam {

struct ContactKey {
  int i = -1;
  int j = -1;  // particle, or a wall (IsWallIndex)
  std::array<int, 2> image = {0, 0};
};

struct ClosureOptions {
  int iterations = 4;
  double tolerance = 1e-13;  // |gap| reached, length units
};

struct ClosureReport {
  bool closed = false;            // every chosen gap within the tolerance
  double max_gap = 0.0;           // largest |gap| of the chosen contacts afterwards
  double max_displacement = 0.0;  // largest particle displacement (including the affine part)
  int iterations = 0;
};

ClosureReport CloseContacts(Scene& scene, const std::vector<ContactKey>& contacts,
                            const ClosureOptions& options = {});

}  // namespace unjam
