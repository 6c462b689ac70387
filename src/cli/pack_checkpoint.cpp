#include "pack_checkpoint.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "unjam/io/checkpoint.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/read_text.hpp"

namespace unjam::cli {

namespace {

nlohmann::json Progress(const RelaxReport& r, double seconds) {
  return {{"steps", r.steps},
          {"static_checks", r.static_checks},
          {"refined_checks", r.refined_checks},
          {"unconverged_steps", r.unconverged_steps},
          {"calm_steps", r.calm_steps},
          {"next_attempt", r.next_attempt},
          {"closure_displacement", r.closure_displacement},
          {"seconds", seconds}};
}

RelaxReport ReportFrom(const nlohmann::json& p, const std::string& path) {
  RelaxReport r;
  try {
    r.steps = p.at("steps").get<int>();
    r.static_checks = p.at("static_checks").get<int>();
    r.refined_checks =
        p.value("refined_checks", 0);  // absent from checkpoints made before the option
    r.unconverged_steps = p.at("unconverged_steps").get<int>();
    r.calm_steps = p.at("calm_steps").get<int>();
    r.next_attempt = p.at("next_attempt").get<int>();
    r.closure_displacement = p.at("closure_displacement").get<double>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, std::string("malformed checkpoint progress: ") + e.what());
  }
  return r;
}

void Load(Simulation& sim, const Checkpoint& c) {
  sim.mutable_scene() = c.scene;
  sim.RestoreWarmStart(c.warm_start);
}

}  // namespace

PackCheckpointer::PackCheckpointer(std::string path, nlohmann::json parameters, bool enabled)
    : path_(std::move(path)), parameters_(std::move(parameters)), enabled_(enabled) {}

RelaxReport PackCheckpointer::Resume(Simulation& sim) {
  if (!enabled_ || !std::filesystem::exists(path_)) return {};
  const Checkpoint c = ParseCheckpoint(ReadInputText(path_), path_);
  if (c.parameters != parameters_) {
    std::string differences;
    for (const auto& [key, value] : parameters_.items()) {
      const nlohmann::json saved = c.parameters.value(key, nlohmann::json());
      if (saved != value)
        differences += " " + key + " " + saved.dump() + " (this run: " + value.dump() + ")";
    }
    throw std::invalid_argument(path_ +
                                ": checkpoint of a run with other parameters:" + differences +
                                "; delete it to start afresh, or choose another --checkpoint");
  }
  Load(sim, c);
  previous_seconds_ = c.progress.value("seconds", 0.0);
  const RelaxReport r = ReportFrom(c.progress, path_);
  std::fprintf(stderr, "unjam pack: resuming from %s at step %d\n", path_.c_str(), r.steps);
  return r;
}

void PackCheckpointer::Save(Simulation& sim, const RelaxReport& report) {
  if (!enabled_) return;
  const double seconds =
      previous_seconds_ +
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  Checkpoint c{parameters_, Progress(report, seconds), sim.scene(), sim.WarmStartImpulses()};
  c.scene.forces.clear();
  const std::string text = FormatCheckpoint(c);
  WriteFileAtomically(path_, text);
  // Continue from what was written, so that a resumed run cannot differ by a bit.
  Load(sim, ParseCheckpoint(text, path_));
}

void PackCheckpointer::Remove() {
  if (!enabled_) return;
  std::error_code ignored;
  std::filesystem::remove(path_, ignored);
}

}  // namespace unjam::cli
