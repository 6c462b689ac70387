// The configuration of `unjam study` (docs/friction-study.md): which packings to make, how
// to perturb them and where to write. A JSON file; `sizes` holds named variants (JSON merge
// patches over the file, e.g. "small" and "paper"), one of which `--size` applies.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace unjam {

// Packings under a pressure bath in a periodic cell, perturbed by contact openings.
struct PressureSet {
  int n = 500;            // free disks
  double pressure = 1.0;  // P_ext
  std::vector<double> mu;
  std::vector<std::uint64_t> seeds;
  int openings = 0;  // contacts opened per packing, drawn with the packing's seed
  std::vector<std::string> modes{"fixed-pressure"};  // fixed-pressure, fixed-volume
  bool bounds = true;                                // the LP interval of every opened contact
  int max_steps = 1000000;  // `unjam pack --max-steps`: a packing not static by then is left out
};

// Piles settled under gravity on a rough bed, perturbed by top and bottom shifts.
struct GravitySet {
  int n = 400;
  double width = 25.0;
  std::vector<double> mu;
  std::vector<std::uint64_t> seeds;
  std::vector<std::string> sides{"top", "bottom"};
  bool bounds = true;       // the LP interval of every shift's critical force
  int max_steps = 1000000;  // `unjam pack --max-steps`
};

struct StudyConfig {
  std::string file;  // where it was read from
  std::string size;  // the applied variant of `sizes` ("" if none)
  std::string description;
  std::filesystem::path output;    // the results folder
  std::filesystem::path packings;  // the packing cache (default: OUTPUT/packings)
  int threads = 0;                 // 0: every core
  std::vector<PressureSet> pressure;
  std::vector<GravitySet> gravity;
  nlohmann::json resolved;  // the configuration after the variant, as it is run
};

// Reads and checks CONFIG, applying the variant `size` of its "sizes" ("" for none). Throws
// InputError naming the file, and the line of the offending key where it can be found, for
// malformed JSON, an unknown key, a missing or ill-typed value, or an unknown size.
StudyConfig ReadStudyConfig(const std::filesystem::path& path, const std::string& size);

}  // namespace unjam
