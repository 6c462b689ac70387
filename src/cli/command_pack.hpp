#pragma once

#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace unjam::cli {

struct PackFlags {
  std::string protocol = "gravity";
  int n = 1600;
  double mu = 0.5;
  double width = 100.0;
  double initial_fraction = 0.35;
  std::uint64_t seed = 1;
  double dt = 5e-3;
  double step_tol = 1e-8;
  double rest_speed = 1e-6;
  int max_steps = 1000000;
  std::string output;
  bool json = false;
  bool quiet = false;

  void Register(CLI::App& app);
};

int RunPack(const PackFlags& flags, const std::string& command_line);
int RunMainJob();

}  // namespace unjam::cli
