// `unjam bounds`: admissible-force bounds per contact and the degree of force
// indeterminacy of a static packing (docs/indeterminacy.md, docs/cli.md).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"

namespace unjam::cli {

struct BoundsFlags {
  std::string file;
  std::string contacts = "all";
  std::string lp = "clp";
  bool cold = false;
  bool compare_perturb = false;
  std::string mode = "fixed-pressure";
  double gap_tolerance = 1e-9;
  int threads = 0;
  std::string output;
  bool json = false;

  void Register(CLI::App& app);
};

int RunBounds(const BoundsFlags& flags);

}  // namespace unjam::cli
