// Grains that a rigid step from rest may let fall: under gravity, a free grain every one of
// whose closed contacts lies above its centre (the normal to the neighbour, n, points
// against gravity: n·g < 0). A fall of that grain alone opens every one of its contacts,
// so "no impulse on it, d = g Δt²" obeys their Signorini and Coulomb laws. With friction
// a self-stress of its neighbours can hold it up, and then every step from rest, perturbed
// or not, has a solution in which it falls beside the one in which it stays: a choice
// between motions that rigid grains leave open (docs/perturbations.md, "At μ = 1").
// Grains without contacts are not counted (they are not at rest), nor fixed ones, nor
// clusters that could only fall together.
#pragma once

#include <vector>

#include "unjam/contacts/contact.hpp"
#include "unjam/scene/scene.hpp"

namespace unjam {

// Indices of the hanging grains of `scene` among the closed `contacts` (as DetectContacts
// returns them), in increasing order; empty without gravity.
std::vector<int> HangingGrains(const Scene& scene, const std::vector<Contact>& contacts);

}  // namespace unjam
