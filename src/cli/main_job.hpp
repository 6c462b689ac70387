// `unjam` without a command: the main job on the bundled default packing (docs/cli.md).
#pragma once

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace unjam::cli {

struct MainJobFlags {
  int sample = 8;          // contacts opened
  std::uint64_t seed = 1;  // of the sample (as `unjam perturb --sample N --seed S`)
  std::string out = "unjam-main-job";
  int threads = 0;  // 0: all cores

  void Register(CLI::App& app);  // top-level options, used only without a command
};

int RunMainJob(const MainJobFlags& flags);

}  // namespace unjam::cli
