// `unjam study CONFIG`: the friction study from one command (docs/friction-study.md). Makes
// the configured packings (cached by their parameters), perturbs them, bounds the same
// perturbations by linear programs, and writes the tables, the figures and a report. Every
// step resumes: a killed study rerun with the same command repeats no finished work.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace unjam::cli {

struct StudyFlags {
  std::string config;
  std::string size;                  // a variant of the config's "sizes"
  std::string output;                // -o: overrides the config's "output"
  std::optional<int> threads;        // overrides the config's "threads"
  std::optional<double> time_limit;  // --time-limit S: start no step after S seconds
  bool plan_only = false;            // --plan: list the steps and stop
  bool quiet = false;

  void Register(CLI::App& app);
};

int RunStudy(const StudyFlags& flags);

}  // namespace unjam::cli
