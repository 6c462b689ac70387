// Shared pieces of the command-line front end: exit codes, solver options, output helpers.
// The CLI holds no physics: every number it prints comes from the library.
#pragma once

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "unjam/io/json_lines.hpp"  // NumberOrNull
#include "unjam/protocols/perturbation.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/scene/scene.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam::cli {

// Range checks whose message names the rule, not CLI11's 300-digit bound of a double.
inline CLI::Validator AtLeast(double lowest, bool inclusive, const std::string& rule) {
  return CLI::Validator(
      [=](std::string& v) {
        double x = 0.0;
        try {
          x = std::stod(v);
        } catch (const std::exception&) {
          return "must be a number, got " + v;
        }
        return (inclusive ? x >= lowest : x > lowest) ? std::string()
                                                      : "must be " + rule + ", got " + v;
      },
      "NUMBER " + rule);
}
inline CLI::Validator NonNegative() { return AtLeast(0.0, true, ">= 0"); }
inline CLI::Validator Positive() { return AtLeast(0.0, false, "> 0"); }

// Exit codes (docs/cli.md).
enum ExitCode : int {
  kOk = 0,
  kInputError = 1,     // a file could not be read or is invalid
  kUsageError = 2,     // unknown option, bad option value
  kNotConverged = 3,   // --require-converged and the solver did not converge
  kInternalError = 4,  // anything else (a bug: please report)
  kCheckFailed = 5,    // `unjam check` found a silent failure (docs/stability.md)
};

// Solver options as the CLI spells them, shared by every command that solves.
struct SolverFlags {
  std::string backend = "nsgs";
  bool backend_may_be_auto = false;  // "auto": the command picks (perturb)
  std::string order = "random";
  std::string nlopt_algorithm = "lbfgs";
  int max_iterations = SolverOptions{}.nsgs.max_sweeps;  // SolverOptions::SetIterationLimit
  SolverOptions options;
  bool require_converged = false;

  void Register(CLI::App& app);
  SolverOptions Resolve() const;  // throws std::invalid_argument on a bad value
};

// The thread count of a `--threads N` option: N, or every core for 0.
int ThreadsFromOption(int requested);

// The bundled default packing (problems/pressure-n500-mu0.5.unjam), found from the working
// directory or the source tree.
std::string DefaultPackingPath();

nlohmann::json ToJson(const SolveReport& report);
// printf-style formatting into a string (lines of CSV and progress, under 512 characters).
std::string Format(const char* fmt, auto... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

// The optional figure step: runs scripts/NAME of the source tree with the Python 3 (and
// matplotlib) found at configure time, the arguments each quoted for the shell; stdout is
// discarded. kSkipped where the build has no figure step (UNJAM_FIGURES off, or no Python
// with matplotlib when configured).
enum class FigureStatus { kDrawn, kSkipped, kFailed };
FigureStatus RunPlotScript(const std::string& name, const std::vector<std::string>& args);
// Why figures are skipped, for the message a command prints.
const char* FiguresSkippedReason();

// Every digit of a finite number (%.17g); empty for no number (CSV).
std::string ExactNumber(double x);

// FNV-1a of a file, 16 hex digits: a resumed run must start from the same packing.
std::string FileFingerprint(const std::string& path);
std::string EffectsSummary(const Scene& scene);
const char* PeriodicityName(Periodicity p);

int RunInfo(const std::string& path, bool json);

// `--top`, `--bottom`, `--shift-down P`, `--shift-up P` (perturb, bounds): which particle
// shifts are asked for. The library chooses and checks them (ShiftTargets).
struct ShiftFlags {
  bool top = false, bottom = false;
  std::optional<int> down, up;  // particle P
  int Given() const { return top + bottom + down.has_value() + up.has_value(); }
  // The selection of the flag given (the first, were several); none without one.
  std::optional<ShiftSelection> Selection() const;
};

}  // namespace unjam::cli
