// Checkpoints of `unjam pack` (io/checkpoint.hpp): save the run every so many steps, resume
// an interrupted run from its checkpoint when the same command is run again.
#pragma once

#include <chrono>
#include <string>

#include <nlohmann/json.hpp>

#include "unjam/protocols/relax.hpp"

namespace unjam::cli {

class PackCheckpointer {
 public:
  PackCheckpointer(std::string path, nlohmann::json parameters, bool enabled);

  // If a checkpoint exists: loads it into `sim`, says so on stderr and returns its progress. Throws
  // std::invalid_argument if it was written by a run with other parameters, InputError if it
  // is not a valid checkpoint.
  RelaxReport Resume(Simulation& sim);
  // Writes the state atomically, then continues from exactly what was written.
  void Save(Simulation& sim, const RelaxReport& report);
  void Remove();
  double PreviousSeconds() const { return previous_seconds_; }

 private:
  std::string path_;
  nlohmann::json parameters_;
  bool enabled_;
  double previous_seconds_ = 0.0;  // time spent by the runs before a resume
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace unjam::cli
