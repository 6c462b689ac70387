// `unjam perturb`: contact openings or particle shifts of a static packing, one by one from
// the same state, and what they measure (docs/perturbations.md, docs/cli.md).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "unjam/protocols/perturbation.hpp"

namespace unjam::cli {

struct PerturbFlags {
  std::string file;
  std::optional<int> contact;  // --contact K
  bool all = false;
  std::optional<int> sample;  // --sample N
  std::uint64_t seed = 1;
  ShiftFlags shifts;  // --top, --bottom, --shift-down P, --shift-up P
  std::string mode = "fixed-pressure";
  double gap = 1e-9;
  double dt = 1.0;
  double response_tol = 1e-2;
  int threads = 0;  // 0: all cores
  SolverFlags solver;
  std::string output_dir;
  std::optional<double> time_limit;  // --time-limit S: start no perturbation after S seconds
  bool check_linearity = true;       // --no-check-linearity turns it off
  bool cold_check = false;           // --cold-check: the 10 xi check from zero impulses
  std::string member = "path";
  bool json = false;
  bool summary = true;  // false: nothing on stdout (a study's steps: the study prints one report)
  bool quiet = false;
  CLI::App* app = nullptr;  // to ask whether --tol was given

  void Register(CLI::App& app);
};

int RunPerturb(const PerturbFlags& flags);

// The full fields of one perturbation in DIR: displacement.csv (particle, x, y, radius,
// dx, dy, rotation), response.vtk (ParaView) and response.xyz (OVITO).
void WriteFullField(const std::filesystem::path& dir, const PerturbationBase& base,
                    const PerturbationResult& result);

}  // namespace unjam::cli
