// `unjam` with no arguments: the main job on the bundled default packing.
#include <cstdio>

#include "cli_common.hpp"
#include "command_pack.hpp"
#include "command_solve.hpp"

namespace unjam::cli {

int RunMainJob() {
  const std::string path = DefaultPackingPath();
  std::printf("unjam: main job on the bundled default packing\n\n");
  std::printf("== what the packing holds (unjam info %s)\n", path.c_str());
  if (int rc = RunInfo(path, false); rc != kOk) return rc;
  std::printf("\n== its static contact forces (unjam solve %s --tol 1e-10)\n", path.c_str());
  SolveFlags flags;
  flags.file = path;
  flags.solver.options.tolerance = 1e-10;
  return RunSolve(flags);
}

}  // namespace unjam::cli
