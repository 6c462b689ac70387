// Checkpoints of long runs (`unjam pack`): everything needed to resume a run so that it ends
// bit for bit as an uninterrupted one would (docs/format.md, "Checkpoints").
//
// One JSON object: {"format": "unjam-checkpoint", "version": 1, "parameters": {...},
// "progress": {...}, "packing": "<the .unjam text of the state>", "warm_start": [[i, j,
// image_x, image_y, impulse_n, impulse_t], ...]}. The packing holds the positions,
// velocities, spins and cell state; the warm start is the last step's impulses. Doubles are
// written in the shortest form that reads back to the same bits, so a resumed run continues
// exactly. `parameters` and `progress` are opaque to this module: the command that writes a
// checkpoint decides what they hold.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "unjam/scene/scene.hpp"

namespace unjam {

struct Checkpoint {
  nlohmann::json parameters;
  nlohmann::json progress;
  Scene scene;
  std::vector<ContactForce> warm_start;  // impulses, as Simulation::WarmStartImpulses
};

std::string FormatCheckpoint(const Checkpoint& checkpoint);
// Throws InputError naming `name` for anything that is not a valid checkpoint.
Checkpoint ParseCheckpoint(std::string_view text, const std::string& name);

}  // namespace unjam
