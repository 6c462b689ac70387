// `unjam check PATH...`: the hard-case catalogue on every backend; the stability table
// (docs/stability.md, docs/cli.md).
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace unjam::cli {

struct CheckFlags {
  std::vector<std::string> paths;     // case files, or folders of them
  std::vector<std::string> backends;  // empty: every available backend
  double tolerance = 1e-10;
  int steps = 100;
  double dt = 1e-3;
  double max_step_seconds = 60.0;
  SolverFlags solver;
  std::string output_dir;
  bool json = false;
  bool quiet = false;

  void Register(CLI::App& app);
};

int RunCheck(const CheckFlags& flags);

}  // namespace unjam::cli
