// `unjam pack`: make a static packing (constant pressure or gravity) and save it.
#pragma once

#include <optional>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"

namespace unjam::cli {

struct PackFlags {
  std::string protocol;
  int n = 0;  // 0: the protocol's default
  double mu = 0.5;
  double pressure = 1.0;
  double cell_mass = 100.0;
  double width = 100.0;
  std::optional<double> initial_fraction;
  std::uint64_t seed = 1;
  std::optional<double> dt;
  std::optional<double> step_tol;  // default: the backend's (StepTolerance)
  std::optional<int> step_iter;    // default: StepIterations
  std::string backend = "auto";    // auto: newton without friction, nsgs with it
  std::optional<std::string>
      order;  // NSGS sweep order of the steps and the static solves; default: Order
  double rest_speed = 1e-2;
  int check_iter = 100000;
  int refine_iter = 30000;
  double closure_gap = 1e-6;    // a certificate may load and close contacts up to this gap
  bool certificate_lp = false;  // a certificate asks the LP when its projections fail
  int threads = 1;              // NSGS threads; 0: all cores
  int max_steps = 1000000;
  std::string output;
  std::string checkpoint;       // default: OUTPUT.checkpoint
  int checkpoint_every = 1000;  // steps; 0: no checkpoints
  bool json = false;
  bool summary = true;  // false: nothing on stdout (a study's steps: the study prints one report)
  bool quiet = false;

  void Register(CLI::App& app);
  // Every parameter that decides the packing, defaults resolved: stored in the file (as a
  // command line that remakes it) and in checkpoints (a resumed run must match it).
  nlohmann::json Parameters() const;
  std::string Backend() const;   // --backend with auto resolved
  double StepTolerance() const;  // --step-tol, or the resolved backend's default
  int StepIterations() const;    // --step-iter, or the protocol's default
  std::string Order() const;     // --order, or the protocol's default
  int Threads() const;           // --threads with 0 resolved to the cores
  // The command line that remakes the packing, every parameter spelled out, and the version
  // that made it: "unjam pack --backend ... (unjam 0.1.0)", stored in the file.
  std::string Provenance() const;
};

int RunPack(const PackFlags& flags);

}  // namespace unjam::cli
