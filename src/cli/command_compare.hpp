// `unjam compare`: every backend on every problem at every tolerance: what accuracy costs
// in time (docs/accuracy-vs-time.md, docs/cli.md).
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace unjam::cli {

struct CompareFlags {
  std::vector<std::string> files;
  std::vector<std::string> backends;  // empty: every available backend
  std::vector<double> tolerances = {1e-4, 1e-8, 1e-12};
  int openings = 0;  // contact-opening problems per packing
  std::uint64_t seed = 1;
  double reference_tolerance = 1e-13;
  std::string reference_backend = "newton";
  SolverFlags solver;  // iteration limits and the like
  std::string output_dir;
  bool json = false;
  bool quiet = false;

  void Register(CLI::App& app);
};

int RunCompare(const CompareFlags& flags);

}  // namespace unjam::cli
