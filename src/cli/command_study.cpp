#include "command_study.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "command_bounds.hpp"
#include "command_pack.hpp"
#include "command_perturb.hpp"
#include "mpi_session.hpp"
#include "study_outputs.hpp"
#include "unjam/io/output_lock.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/read_text.hpp"
#include "unjam/protocols/perturbation.hpp"

namespace unjam::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// One resumable piece of work: done() says whether an earlier run finished it.
struct Step {
  std::string kind;  // pack, perturb, bounds: steps of one kind take alike times
  std::string label;
  std::function<bool()> done;
  std::function<int()> run;  // an exit code (ExitCode)
};

PackFlags PackFlagsOf(const StudyPacking& p, bool quiet) {
  PackFlags f;
  f.protocol = p.key.protocol;
  f.n = p.key.n;
  f.mu = p.key.mu;
  f.seed = p.seed;
  if (p.key.protocol == "gravity") f.width = p.key.width;
  else f.pressure = p.key.pressure;
  f.output = p.file.string();
  f.max_steps = p.max_steps;
  f.summary = false;
  f.quiet = quiet;
  return f;
}

// The command part of a provenance line, without "(unjam VERSION)": a packing made by
// another version from the same parameters is the same packing.
std::string CommandOf(const std::string& provenance) {
  return provenance.substr(0, provenance.rfind(" (unjam "));
}

bool PackingDone(const StudyPacking& p) {
  if (!fs::exists(p.file)) return false;
  const std::string want = CommandOf(PackFlagsOf(p, true).Provenance());
  const std::string have = CommandOf(ReadPacking(p.file.string()).provenance);
  if (have != want) {
    throw InputError(p.file.string(), 0,
                     "is cached for other parameters: it was made by `" + have +
                         "`, the study needs `" + want +
                         "`; move it away or choose another "
                         "\"packings\" folder");
  }
  return true;
}

bool PerturbationsDone(const StudyRunPlan& r) {
  const fs::path summary = r.dir / "summary.json";
  if (!fs::exists(summary)) return false;
  const nlohmann::json s = nlohmann::json::parse(ReadInputText(summary), nullptr, false);
  return s.is_object() && s.value("complete", false);
}

PerturbFlags PerturbFlagsOf(const StudyPacking& p, const StudyRunPlan& r, int threads, bool quiet) {
  PerturbFlags f;
  f.file = p.file.string();
  if (r.kind == "top") f.shifts.top = true;
  else if (r.kind == "bottom") f.shifts.bottom = true;
  else {
    f.sample = r.openings;
    f.seed = p.seed;
    f.mode = r.kind;
  }
  f.solver.backend = "auto";
  f.solver.backend_may_be_auto = true;
  f.threads = threads;
  f.output_dir = r.dir.string();
  f.summary = false;
  f.quiet = quiet;
  return f;
}

// The contacts `perturb --sample N --seed S` opens, as `bounds --contacts` numbers them.
std::string OpenedContacts(const StudyPacking& p, const StudyRunPlan& r) {
  const Scene scene = ReadPacking(p.file.string());
  PerturbationOptions options;
  options.cell = CellConditionFromString(r.kind);
  const PerturbationBase base = PreparePerturbations(scene, options);
  const std::vector<PerturbationTarget> all = ContactTargets(base);
  const std::vector<PerturbationTarget> opened = SampleTargets(all, r.openings, p.seed);
  std::string list;
  for (const PerturbationTarget& t : opened) {
    for (std::size_t k = 0; k < all.size(); ++k) {
      if (all[k].i == t.i && all[k].j == t.j && all[k].image == t.image) {
        list += (list.empty() ? "" : ",") + std::to_string(k);
        break;
      }
    }
  }
  return list;
}

BoundsFlags BoundsFlagsOf(const StudyPacking& p, const StudyRunPlan& r, int threads, bool quiet) {
  BoundsFlags f;
  f.file = p.file.string();
  if (r.kind == "top") f.shifts.top = true;
  else if (r.kind == "bottom") f.shifts.bottom = true;
  else f.contacts = OpenedContacts(p, r);
  f.threads = threads;
  f.output = r.bounds_csv.string();
  f.summary = false;
  f.quiet = quiet;
  return f;
}

std::vector<Step> StepsOf(const StudyPlan& plan, bool quiet) {
  std::vector<Step> steps;
  for (const StudyPacking& p : plan.packings) {
    steps.push_back({"pack", "pack " + p.name, [&p] { return PackingDone(p); },
                     [&p, quiet] {
                       fs::create_directories(p.file.parent_path());
                       return RunPack(PackFlagsOf(p, quiet));
                     }});
  }
  std::set<fs::path> bounded;
  for (const StudyRunPlan& r : plan.runs) {
    const StudyPacking& p = plan.packings[r.packing];
    steps.push_back(
        {"perturb", "perturb " + p.name + " " + r.kind, [&r] { return PerturbationsDone(r); },
         [&p, &r, &plan, quiet] { return RunPerturb(PerturbFlagsOf(p, r, plan.threads, quiet)); }});
    // The openings of every mode share one bounds CSV: one step for it, with the first mode.
    if (!r.bounds || !bounded.insert(r.bounds_csv).second) continue;
    steps.push_back({"bounds", "bounds " + r.bounds_csv.filename().string() + " " + p.name,
                     [&r] { return fs::exists(r.bounds_csv); },
                     [&p, &r, &plan, quiet] {
                       fs::create_directories(r.bounds_csv.parent_path());
                       return RunBounds(BoundsFlagsOf(p, r, plan.threads, quiet));
                     }});
  }
  return steps;
}

void PrintPlan(const StudyPlan& plan, const std::vector<Step>& steps) {
  std::printf("study %s%s: %zu packings, %zu runs, %zu steps; output %s\n",
              plan.config.file.c_str(),
              plan.config.size.empty() ? "" : (" --size " + plan.config.size).c_str(),
              plan.packings.size(), plan.runs.size(), steps.size(), plan.output.c_str());
  for (const Step& s : steps) std::printf("  %s %s\n", s.done() ? "done" : "todo", s.label.c_str());
}

std::string Duration(double seconds) {
  if (seconds < 120) return Format("%.0f s", seconds);
  if (seconds < 7200) return Format("%.1f min", seconds / 60);
  return Format("%.1f h", seconds / 3600);
}

// Time left: each kind's steps still to do at that kind's mean time so far in this run.
class StepClock {
 public:
  void Add(const std::string& kind, double seconds) {
    total_[kind] += seconds;
    ++count_[kind];
  }
  // `left`: the steps still to do, per kind.
  std::string Remaining(const std::map<std::string, int>& left) const {
    double seconds = 0.0;
    std::string unknown;
    bool any = false;
    for (const auto& [kind, n] : left) {
      if (n == 0) continue;
      any = true;
      const auto it = count_.find(kind);
      if (it == count_.end()) unknown += (unknown.empty() ? "" : ", ") + kind;
      else seconds += total_.at(kind) / it->second * n;
    }
    if (!any) return "nothing left";
    return "about " + Duration(seconds) + " left" +
           (unknown.empty() ? "" : " besides the " + unknown + " steps (not timed yet)");
  }

 private:
  std::map<std::string, double> total_;
  std::map<std::string, int> count_;
};

}  // namespace

void StudyFlags::Register(CLI::App& app) {
  app.add_option("CONFIG", config, "study configuration (JSON, docs/friction-study.md)")
      ->required();
  app.add_option("--size", size, "a variant of the configuration's \"sizes\" (e.g. small, paper)");
  app.add_option("-o,--output", output, "results folder (default: the configuration's \"output\")");
  app.add_option("--threads", threads, "threads of the perturbations and bounds (0: all cores)")
      ->check(NonNegative());
  app.add_option("--time-limit", time_limit,
                 "start no step after S seconds; the tables then hold the finished runs, and the "
                 "same command continues")
      ->check(NonNegative());
  app.add_flag("--plan", plan_only, "list the steps (done or to do) and stop");
  app.add_flag("--quiet", quiet, "no progress on stderr");
}

namespace {

// Where this process stands in an mpirun: whole steps are divided among the ranks (each
// step's own command then runs as one process), packings first, with a barrier after the
// packings and after the rest; rank 0 writes the tables.
struct Ranks {
  MpiSession* mpi = nullptr;
  int rank = 0, size = 1;
  bool Mine(std::size_t index) const { return static_cast<int>(index % size) == rank; }
  int Barrier(int status) const { return mpi != nullptr ? mpi->WorstStatus(status) : status; }
};

// The commands of a step see no MPI session: the study divides its steps, not their work.
class WithoutMpi {
 public:
  WithoutMpi() : saved_(CurrentMpiSession()) { SetCurrentMpiSession(nullptr); }
  ~WithoutMpi() { SetCurrentMpiSession(saved_); }
  WithoutMpi(const WithoutMpi&) = delete;
  WithoutMpi& operator=(const WithoutMpi&) = delete;

 private:
  MpiSession* saved_;
};

// This process's steps: how many are done, and how many of each kind are still to do (kept
// here, not asked of every step again after each one: a step's check reads its files).
struct Progress {
  int done = 0, total = 0, worst = kOk;
  std::map<std::string, int> left;
  StepClock clock;
};

// Runs one step unless an earlier run finished it. Under several ranks an error is a code,
// not an exception, so that every rank reaches the barriers.
void RunStep(const Step& s, const Ranks& ranks, bool quiet, Progress& p) {
  const std::string who = ranks.size > 1 ? Format("study[rank %d]", ranks.rank) : "study";
  int code = kOk;
  --p.left[s.kind];
  try {
    if (s.done()) {
      ++p.done;
      return;
    }
    const auto step_start = Clock::now();
    if (!quiet) std::fprintf(stderr, "%s: %s\n", who.c_str(), s.label.c_str());
    const WithoutMpi single;
    code = s.run();
    p.clock.Add(s.kind, std::chrono::duration<double>(Clock::now() - step_start).count());
    if (code == kOk && s.done()) {
      ++p.done;
      if (!quiet)
        std::fprintf(stderr, "%s: %d of %d steps done; %s\n", who.c_str(), p.done, p.total,
                     p.clock.Remaining(p.left).c_str());
      return;
    }
  } catch (const std::exception& e) {
    if (ranks.size == 1) throw;
    std::fprintf(stderr, "%s: error: %s\n", who.c_str(), e.what());
    code = dynamic_cast<const InputError*>(&e) != nullptr ? int{kInputError} : int{kInternalError};
  }
  std::fprintf(stderr, "%s: %s did not finish (exit %d); the study goes on without it\n",
               who.c_str(), s.label.c_str(), code);
  p.worst = std::max(p.worst, code == kOk ? int{kNotConverged} : code);
}

void WriteOutputs(const StudyPlan& plan, const std::vector<Step>& steps, double seconds) {
  std::vector<StudyRun> runs;
  int done = 0;
  for (const Step& s : steps) done += s.done() ? 1 : 0;
  for (const StudyRunPlan& r : plan.runs) {
    if (!PerturbationsDone(r) || (r.bounds && !fs::exists(r.bounds_csv))) continue;
    runs.push_back(ReadStudyRun(plan, r));
  }
  WriteStudyTables(plan, runs, AggregateStudy(runs), seconds);
  const FigureStatus figures = RunPlotScript("plot_study.py", {plan.output.string()});
  std::printf("study %s: %d of %zu steps done, %zu runs in the tables; %s\n", plan.output.c_str(),
              done, steps.size(), runs.size(), (plan.output / "report.md").c_str());
  if (figures == FigureStatus::kSkipped)
    std::printf("figures skipped: %s\n", FiguresSkippedReason());
  else if (figures == FigureStatus::kFailed)
    std::fprintf(
        stderr, "unjam study: the figures were not drawn (scripts/figures/plot_study.py failed)\n");
  if (done != static_cast<int>(steps.size())) {
    std::fprintf(stderr, "study: %zu steps left; the same command continues\n",
                 steps.size() - static_cast<std::size_t>(done));
  }
}

}  // namespace

int RunStudy(const StudyFlags& f) {
  const auto start = Clock::now();
  StudyConfig config = ReadStudyConfig(f.config, f.size);
  const int threads = ThreadsFromOption(f.threads.value_or(config.threads));
  const StudyPlan plan = MakeStudyPlan(std::move(config), f.output, threads);
  const std::vector<Step> steps = StepsOf(plan, f.quiet);
  Ranks ranks;
  ranks.mpi = CurrentMpiSession();
  if (ranks.mpi != nullptr) {
    ranks.rank = ranks.mpi->rank();
    ranks.size = ranks.mpi->size();
  }
  if (f.plan_only) {
    if (ranks.rank == 0) PrintPlan(plan, steps);
    return kOk;
  }
  fs::create_directories(plan.output);
  std::optional<OutputLock> lock;  // rank 0 holds it for the whole mpirun
  if (ranks.rank == 0) {
    lock.emplace(plan.output / ".study.lock", plan.output.string());
    WriteFileAtomically(plan.output / "study.json", plan.config.resolved.dump(2) + "\n");
  }
  if (ranks.Barrier(kOk) != kOk) return kInputError;  // rank 0 could not take the study

  Progress progress;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    if (!ranks.Mine(k)) continue;
    ++progress.left[steps[k].kind];
    ++progress.total;
  }
  const auto mine = [&](std::size_t k) {
    const bool in_time =
        !f.time_limit ||
        std::chrono::duration<double>(Clock::now() - start).count() < *f.time_limit;
    return ranks.Mine(k) && in_time;
  };
  const std::size_t packs = plan.packings.size();  // StepsOf: the packings first
  for (std::size_t k = 0; k < packs; ++k)
    if (mine(k)) RunStep(steps[k], ranks, f.quiet, progress);
  progress.worst = ranks.Barrier(progress.worst);
  for (std::size_t k = packs; k < steps.size(); ++k)
    if (mine(k)) RunStep(steps[k], ranks, f.quiet, progress);
  const int worst = ranks.Barrier(progress.worst);
  if (ranks.rank != 0) return worst;
  WriteOutputs(plan, steps, std::chrono::duration<double>(Clock::now() - start).count());
  return worst;
}

}  // namespace unjam::cli
