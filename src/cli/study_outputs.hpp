// The plan of `unjam study` and what it writes: where each packing and run lives, what a
// finished run left in its folder (read back into a StudyRun), and the study's tables and
// report (docs/friction-study.md, "Outputs").
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "unjam/analysis/study_table.hpp"
#include "unjam/io/study_config.hpp"

namespace unjam::cli {

struct StudyPacking {
  StudyKey key;  // kind left empty
  std::uint64_t seed = 0;
  std::string name;         // e.g. pressure-n500-p1-mu0.5-seed1
  int max_steps = 1000000;  // the largest of the sets that list it
  std::filesystem::path file;
};

// One packing perturbed one way: openings in one cell mode, or shifts of one side.
struct StudyRunPlan {
  int packing = 0;   // index in StudyPlan::packings
  std::string kind;  // fixed-pressure, fixed-volume, top, bottom
  int openings = 0;  // pressure: contacts sampled (seed: the packing's)
  bool bounds = true;
  std::filesystem::path dir;         // `unjam perturb -o`
  std::filesystem::path bounds_csv;  // `unjam bounds -o` (one per packing for openings)
};

struct StudyPlan {
  StudyConfig config;
  std::filesystem::path output;
  int threads = 1;
  std::vector<StudyPacking> packings;
  std::vector<StudyRunPlan> runs;
};

StudyPlan MakeStudyPlan(StudyConfig config, const std::string& output_override, int threads);

// What a run's folder and its bounds CSV hold (after `perturb` and `bounds`). Throws
// InputError naming a file that is missing or malformed.
StudyRun ReadStudyRun(const StudyPlan& plan, const StudyRunPlan& run);

// OUTPUT/runs.csv (one row per run), OUTPUT/summary-pressure.csv and summary-gravity.csv
// (one row per set), OUTPUT/report.md; each written atomically.
void WriteStudyTables(const StudyPlan& plan, const std::vector<StudyRun>& runs,
                      const std::vector<StudyRow>& rows, double seconds);

}  // namespace unjam::cli
