// Whole-file checks of a parsed packing: indices in range, positions inside periodic
// cells, no overlapping disks. Internal to src/io.
#pragma once

#include <string>
#include <vector>

#include "unjam/io/packing_file.hpp"

namespace unjam::io_internal {

// Line numbers of the entries of a parsed file, so that whole-file checks can still point
// at the offending line.
struct SourceLines {
  int cell = 0;
  int pressure_bath = 0;
  int end = 0;
  std::vector<int> particles;
  std::vector<int> forces;
  std::vector<int> motions;
  std::vector<int> gaps;
};

// Throws InputError (file `name`) for the first problem found.
void CheckPacking(const Scene& scene, const SourceLines& source, const std::string& name,
                  const ReadOptions& options);

}  // namespace unjam::io_internal
