// `unjam solve FILE`: the static contact forces of a saved packing (.unjam), or the solution
// of a stored 2D friction-contact problem (Siconos .dat); docs/cli.md.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace unjam::cli {

struct SolveFlags {
  std::string file;
  SolverFlags solver;
  bool json = false;
  bool forces = false;         // list every contact force (packing) or impulse (.dat)
  std::string output;          // the solved packing, or the impulses of a .dat problem
  std::string export_problem;  // write the contact problem as a Siconos .dat file
  int threads = 1;             // NSGS threads on a packing; 0: all cores

  void Register(CLI::App& app);
};

int RunSolve(const SolveFlags& flags);
// A Siconos .dat problem (dispatched by RunSolve on the extension).
int RunSolveStored(const SolveFlags& flags);
bool IsSiconosFile(const std::string& path);

}  // namespace unjam::cli
