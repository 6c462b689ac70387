// `unjam pack`: make a static packing (constant pressure or gravity) and save it.
#pragma once

#include <optional>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace unjam::cli {

struct PackFlags {
  std::string protocol;
  int n = 0;                        // 0: the protocol's default
  double mu = 0.5;
  double pressure = 1.0;
  double cell_mass = 100.0;
  double width = 100.0;
  std::optional<double> initial_fraction;
  std::uint64_t seed = 1;
  std::optional<double> dt;
  double step_tol = 1e-4;
  int step_iter = 500;
  double rest_speed = 1e-4;
  int check_iter = 100000;
  int max_steps = 1000000;
  std::string output;
  bool json = false;
  bool quiet = false;

  void Register(CLI::App& app);
};

int RunPack(const PackFlags& flags, const std::string& command_line);
int RunMainJob();

}  // namespace unjam::cli
