// `unjam check PATH... [--backends LIST] [--steps N] [-o DIR]`
#include "command_check.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>

#include "check_records.hpp"
#include "command_solve.hpp"
#include "output_paths.hpp"
#include "unjam/io/output_lock.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/siconos_problem.hpp"
#include "unjam/protocols/stability_check.hpp"

namespace unjam::cli {

void CheckFlags::Register(CLI::App& a) {
  a.add_option("PATH", paths, "case files (.unjam, .dat) or folders of them (e.g. problems/hard)")
      ->required();
  a.add_option("--backends", backends, "backends to run, comma-separated (default: all)")
      ->delimiter(',');
  a.add_option("--steps", steps, "Moreau-Jean steps of each case at rest, per backend")
      ->check(NonNegative())
      ->capture_default_str();
  a.add_option("--dt", dt, "time step of those steps")->check(Positive())->capture_default_str();
  a.add_option("--max-step-seconds", max_step_seconds,
               "stop one (case, backend)'s steps after this long (the table says how many ran)")
      ->check(Positive())
      ->capture_default_str();
  solver.Register(a);
  a.remove_option(a.get_option("--backend"));
  a.remove_option(a.get_option("--tol"));
  a.add_option("--tol", tolerance, "tolerance every static solve must reach (unjam residual)")
      ->check(Positive())
      ->capture_default_str();
  a.add_option("-o,--output", output_dir, "directory: stability.csv");
  a.add_flag("--json", json, "one JSON object on stdout");
  a.add_flag("--quiet", quiet, "no progress on stderr");
}

namespace {

bool IsCaseFile(const std::filesystem::path& p) {
  return p.extension() == ".unjam" || IsSiconosFile(p.string());
}

// The case files of the paths: a file as it is, a folder's case files in name order.
std::vector<std::filesystem::path> CaseFiles(const std::vector<std::string>& paths) {
  std::vector<std::filesystem::path> out;
  for (const std::string& path : paths) {
    if (!std::filesystem::is_directory(path)) {
      if (!std::filesystem::exists(path)) throw InputError(path, 0, "no such file or folder");
      out.emplace_back(path);
      continue;
    }
    std::vector<std::filesystem::path> in_folder;
    for (const auto& entry : std::filesystem::directory_iterator(path)) {
      if (entry.is_regular_file() && IsCaseFile(entry.path())) in_folder.push_back(entry.path());
    }
    if (in_folder.empty()) throw InputError(path, 0, "holds no case file (.unjam or .dat)");
    std::sort(in_folder.begin(), in_folder.end());
    out.insert(out.end(), in_folder.begin(), in_folder.end());
  }
  return out;
}

// A file the reader refuses is a case too: refusing an ill-posed problem is the right answer.
StabilityRow Refused(const std::string& name, const InputError& e) {
  StabilityRow row;
  row.name = name;
  row.backend = "-";
  row.report.status = SolveStatus::kUnsupported;
  row.report.message = e.what();
  row.siconos_error = std::nan("");
  row.equilibrium = std::nan("");
  row.verdict = StabilityVerdict::kReported;
  row.message = std::string("refused by the reader: ") + e.what();
  return row;
}

std::string Csv(const std::vector<StabilityRow>& rows) {
  std::ostringstream os;
  os << "case,backend,contacts,status,residual,siconos_error,equilibrium,finite,reproducible,steps,"
        "max_overlap,overlap_growth,energy_change,"
        "seconds,verdict,message\n";
  for (const StabilityRow& r : rows) {
    std::string message = r.message;
    std::replace(message.begin(), message.end(), '"', '\'');
    os << r.name << ',' << r.backend << ',' << r.contacts << ',' << ToString(r.report.status)
       << Format(",%.6e,%.6e,%.6e,", r.report.residual, r.siconos_error, r.equilibrium)
       << (r.finite ? "true" : "false") << ',' << (r.reproducible ? "true" : "false") << ','
       << r.steps
       << Format(",%.6e,%.6e,%.6e,%.6e,", r.max_overlap, r.overlap_growth, r.energy_change,
                 r.report.seconds)
       << ToString(r.verdict) << ",\"" << message << "\"\n";
  }
  return os.str();
}

void PrintRow(std::FILE* out, const StabilityRow& r) {
  std::fprintf(out, "%-30s %-7s %6d %-17s %9.2e %9.2e %9.2e %6d %9.2e %9.2e %8.3f  %s%s%s\n",
               r.name.c_str(), r.backend.c_str(), r.contacts, ToString(r.report.status),
               r.report.residual, r.siconos_error, r.equilibrium, r.steps, r.overlap_growth,
               r.energy_change, r.report.seconds, ToString(r.verdict),
               r.message.empty() ? "" : ": ", r.message.substr(0, 90).c_str());
}

// What makes two runs of `check -o DIR` the same, so that a rerun may take the records back.
nlohmann::json CheckHeader(const CheckFlags& f, const StabilityOptions& o,
                           const std::vector<std::filesystem::path>& files) {
  nlohmann::json cases = nlohmann::json::array();
  for (const std::filesystem::path& file : files)
    cases.push_back({file.filename().string(), FileFingerprint(file.string())});
  const SolverOptions& s = o.solver;
  return {{"unjam_check_records", 1},
          {"cases", cases},
          {"steps", o.steps},
          {"dt", o.dt},
          {"tolerance", s.tolerance},
          {"max_step_seconds", o.max_step_seconds},
          {"max_seconds", NumberOrNull(s.time_limit)},
          {"max_iter", f.solver.max_iterations},
          {"solver",
           {s.nsgs.relaxation, ToString(s.nsgs.order), s.nsgs.seed, s.newton.max_iterations,
            s.newton.warmup_tolerance, s.de_saxce.convex_relaxation, s.ipopt.max_iterations,
            ToString(s.nlopt.algorithm), s.nlopt.max_evaluations, s.lemke.pivots_per_row}}};
}

StabilityCase ReadCase(const std::filesystem::path& file) {
  StabilityCase c{file.filename().string(), {}};
  if (IsSiconosFile(file.string())) c.problem = ReadSiconosProblem(file.string());
  else c.problem = ReadPacking(file.string());
  return c;
}

// The rows of one case, one per backend (or the reader's refusal), each recorded as it comes;
// rows the records already hold are taken from them.
std::vector<StabilityRow> CheckCase(const std::filesystem::path& file, const StabilityOptions& o,
                                    CheckRecords* records, bool quiet) {
  const std::string name = file.filename().string();
  auto done = [&](const std::string& backend) {
    return records != nullptr ? records->Find(name, backend) : nullptr;
  };
  if (const StabilityRow* refused = done("-")) return {*refused};
  std::vector<StabilityRow> rows;
  std::optional<StabilityCase> c;
  for (const std::string& backend : o.backends) {
    if (const StabilityRow* row = done(backend)) {
      rows.push_back(*row);
      continue;
    }
    StabilityRow row;
    try {
      if (!c) c = ReadCase(file);
      StabilityOptions one = o;
      one.backends = {backend};
      row = CheckStability(*c, one).front();
    } catch (const InputError& e) {
      row = Refused(name, e);
    }
    if (records != nullptr) records->Add(row);
    if (!quiet) PrintRow(stderr, row);
    rows.push_back(row);
    if (row.backend == "-") break;
  }
  return rows;
}

}  // namespace

int RunCheck(const CheckFlags& f) {
  const std::vector<std::filesystem::path> files = CaseFiles(f.paths);
  RefuseOutputDirectoryOverInput("-o", f.output_dir,
                                 {"stability.csv", "stability.records.jsonl", ".lock"}, files);
  StabilityOptions o;
  o.backends = f.backends.empty() ? AvailableBackends() : f.backends;
  for (const std::string& b : o.backends) MakeSolver(b);  // an unknown name fails before any work
  o.solver = f.solver.Resolve();
  o.solver.tolerance = f.tolerance;
  o.steps = f.steps;
  o.dt = f.dt;
  o.max_step_seconds = f.max_step_seconds;
  std::optional<OutputLock> lock;
  std::optional<CheckRecords> records;
  if (!f.output_dir.empty()) {
    std::filesystem::create_directories(f.output_dir);
    lock.emplace(std::filesystem::path(f.output_dir) / ".lock", f.output_dir);
    records.emplace(f.output_dir, CheckHeader(f, o, files));
    if (records->Resumed() > 0 && !f.quiet)
      std::fprintf(stderr, "resuming: %zu rows from %s\n", records->Resumed(),
                   (std::filesystem::path(f.output_dir) / "stability.records.jsonl").c_str());
  }
  std::vector<StabilityRow> rows;
  for (const std::filesystem::path& file : files) {
    for (const StabilityRow& r : CheckCase(file, o, records ? &*records : nullptr, f.quiet))
      rows.push_back(r);
  }
  const bool failed = std::any_of(rows.begin(), rows.end(), [](const StabilityRow& r) {
    return r.verdict == StabilityVerdict::kFailed;
  });
  if (!f.output_dir.empty()) {
    WriteFileAtomically(std::filesystem::path(f.output_dir) / "stability.csv", Csv(rows));
    records->Remove();
  }
  if (f.json) {
    nlohmann::json out = {{"cases", files.size()},
                          {"backends", o.backends},
                          {"tolerance", o.solver.tolerance},
                          {"steps", o.steps},
                          {"failed", failed}};
    for (const StabilityRow& r : rows) out["rows"].push_back(RowJson(r));
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("%-30s %-7s %6s %-17s %9s %9s %9s %6s %9s %9s %8s  %s\n", "case", "backend",
                "contacts", "status", "residual", "siconos", "equilibr.", "steps", "d_overlap",
                "d_energy", "seconds", "verdict");
    for (const StabilityRow& r : rows) PrintRow(stdout, r);
  }
  return failed ? kCheckFailed : kOk;
}

}  // namespace unjam::cli
