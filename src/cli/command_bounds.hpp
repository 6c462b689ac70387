// `unjam bounds`: admissible-force bounds per contact and the degree of force
// indeterminacy of a static packing, or bounds of the critical forces of particle shifts
// (docs/indeterminacy.md, docs/cli.md).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include <optional>

#include "cli_common.hpp"
#include "unjam/indeterminacy/equilibrium_system.hpp"

namespace unjam::cli {

struct BoundsFlags {
  std::string file;
  std::string contacts = "all";
  ShiftFlags shifts;  // particle shifts instead of contacts (RunShiftBounds)
  bool Shifts() const { return shifts.Given() > 0; }
  std::string lp = "clp";
  bool cold = false;
  bool compare_perturb = false;
  std::string mode = "fixed-pressure";
  double gap_tolerance = 1e-9;
  int threads = 0;
  std::string output;
  std::optional<double> time_limit;  // seconds: no LP starts after it (contacts only)
  bool json = false;
  bool summary = true;  // false: nothing on stdout (a study's steps: the study prints one report)
  bool quiet = false;   // no progress on stderr

  void Register(CLI::App& app);
  // The ensemble's contacts: gaps up to --gap-tol (checked: std::invalid_argument).
  EquilibriumSystemOptions SystemOptions() const;
};

int RunBounds(const BoundsFlags& flags);

// `--top`, `--bottom`, `--shift-down P`, `--shift-up P`: bounds of the shifts' critical forces
// (command_bounds_shifts.cpp).
int RunShiftBounds(const BoundsFlags& flags);

}  // namespace unjam::cli
