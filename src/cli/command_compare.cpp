// `unjam compare FILE... [--backends LIST] [--tols LIST] [--openings N] [-o DIR]`
#include "command_compare.hpp"

#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "output_paths.hpp"
#include "unjam/io/output_lock.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/siconos_problem.hpp"
#include "unjam/protocols/perturbation.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/solvers/backend_comparison.hpp"

namespace unjam::cli {

void CompareFlags::Register(CLI::App& a) {
  a.add_option(
       "FILE", files,
       "packings (.unjam: their static problem from cold) and stored problems (.dat, Siconos)")
      ->required();
  a.add_option("--backends", backends, "backends to compare, comma-separated (default: all)")
      ->delimiter(',');
  a.add_option("--tols", tolerances, "tolerances on the unjam residual, comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  a.add_option("--openings", openings,
               "also N contact-opening problems per packing (as `unjam perturb --sample N`)")
      ->capture_default_str();
  a.add_option("--seed", seed, "seed of the opening sample")->capture_default_str();
  a.add_option("--ref-tol", reference_tolerance, "tolerance of the reference solution")
      ->capture_default_str();
  a.add_option("--ref-backend", reference_backend, "backend of the reference solution")
      ->capture_default_str();
  solver.Register(a);
  a.remove_option(a.get_option("--backend"));
  a.remove_option(a.get_option("--tol"));
  a.add_option("-o,--output", output_dir,
               "directory: compare.csv, summary.json, work-precision.png, profiles.png");
  a.add_flag("--json", json, "one JSON object on stdout");
  a.add_flag("--quiet", quiet, "no progress on stderr");
}

namespace {

bool IsStoredProblem(const std::string& path) {
  return std::filesystem::path(path).extension() == ".dat";
}

std::string Stem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

// The problems of one file: a stored problem as it is; a packing's static step from zero
// impulses (a solve from its stored forces would cost nothing), and its openings from the
// static forces, as `unjam perturb` poses them.
void AddProblems(const std::string& path, const CompareFlags& f,
                 std::vector<ComparisonProblem>& out) {
  if (IsStoredProblem(path)) {
    out.push_back({Stem(path), ReadSiconosProblem(path), {}});
    return;
  }
  const Scene scene = ReadPacking(path);
  StaticProblem s = PoseStaticProblem(scene, {});
  out.push_back({Stem(path) + " static", std::move(s.assembled.problem), {}});  // from zero
  if (f.openings <= 0) return;
  if (scene.forces.empty())
    throw InputError(path, 0, "stores no static forces, which --openings starts from");
  const PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  for (const PerturbationTarget& t : SampleTargets(ContactTargets(base), f.openings, f.seed)) {
    StaticProblem opening = PosePerturbationProblem(base, t, o);
    out.push_back({Stem(path) + Format(" opening %d-%d", t.i, t.j),
                   std::move(opening.assembled.problem), std::move(opening.guess)});
  }
}

std::string Csv(const std::vector<ComparisonRun>& runs) {
  std::ostringstream os;
  os << "problem,backend,tolerance,status,converged,iterations,residual,force_distance,seconds\n";
  for (const ComparisonRun& r : runs) {
    os << '"' << r.problem << '"' << ',' << r.backend << Format(",%.3g,", r.tolerance)
       << ToString(r.report.status) << ',' << (r.report.converged() ? "true" : "false")
       << Format(",%d,%.6e,%.6e,%.6e\n", r.report.iterations, r.report.residual, r.force_distance,
                 r.report.seconds);
  }
  return os.str();
}

}  // namespace

int RunCompare(const CompareFlags& f) {
  RefuseOutputDirectoryOverInput(
      "-o", f.output_dir,
      {"compare.csv", "summary.json", "work-precision.png", "profiles.png", ".lock"},
      {f.files.begin(), f.files.end()});
  ComparisonOptions o;
  o.backends = f.backends.empty() ? AvailableBackends() : f.backends;
  o.tolerances = f.tolerances;
  for (double t : o.tolerances) {
    if (!(t > 0.0)) throw std::invalid_argument("--tols: every tolerance must be > 0");
  }
  if (f.openings < 0) throw std::invalid_argument("--openings must be >= 0");
  o.solver = f.solver.Resolve();
  o.reference_backend = f.reference_backend;
  o.reference_tolerance = f.reference_tolerance;
  MakeSolver(o.reference_backend);
  std::vector<ComparisonProblem> problems;
  for (const std::string& path : f.files) AddProblems(path, f, problems);
  // The output is claimed before any solve: an output that cannot be written, or that
  // another run writes, is refused at once rather than after the whole comparison.
  std::optional<OutputLock> lock;
  if (!f.output_dir.empty()) {
    std::filesystem::create_directories(f.output_dir);
    lock.emplace(std::filesystem::path(f.output_dir) / ".lock", f.output_dir);
  }

  std::vector<ComparisonRun> runs;
  const std::vector<ComparisonReference> refs =
      CompareBackends(problems, o, [&](const ComparisonRun& r) {
        if (!f.quiet) {
          std::fprintf(
              stderr,
              "compare %s: %-7s tol %.0e  %s, residual %.2e, %d it, %.3f s, force distance %.2e\n",
              r.problem.c_str(), r.backend.c_str(), r.tolerance, ToString(r.report.status),
              r.report.residual, r.report.iterations, r.report.seconds, r.force_distance);
        }
        runs.push_back(r);
      });
  nlohmann::json out = {{"problems", problems.size()},
                        {"backends", o.backends},
                        {"tolerances", o.tolerances},
                        {"runs", runs.size()}};
  for (std::size_t k = 0; k < problems.size(); ++k) {
    out["references"].push_back({{"problem", problems[k].name},
                                 {"source", refs[k].source},
                                 {"residual", refs[k].residual}});
  }
  int rc = kOk;
  if (!f.output_dir.empty()) {
    const std::filesystem::path dir = f.output_dir;
    WriteFileAtomically(dir / "compare.csv", Csv(runs));
    WriteFileAtomically(dir / "summary.json", out.dump(2) + "\n");
    const FigureStatus figures = RunPlotScript("plot_compare.py", {dir.string()});
    if (figures == FigureStatus::kSkipped)
      std::fprintf(stderr, "unjam: figures skipped: %s\n", FiguresSkippedReason());
    if (figures == FigureStatus::kFailed) {
      std::fprintf(
          stderr,
          "unjam: error: the figures were not drawn (%s scripts/figures/plot_compare.py failed)\n",
          UNJAM_PYTHON);
      rc = kInternalError;
    }
    out["output"] = f.output_dir;
  }
  if (f.json) {
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("%-32s %-8s %8s %-16s %10s %8s %10s %10s\n", "problem", "backend", "tol", "status",
                "residual", "iters", "seconds", "|r-r_ref|");
    for (const ComparisonRun& r : runs) {
      std::printf("%-32s %-8s %8.0e %-16s %10.2e %8d %10.4f %10.2e\n", r.problem.c_str(),
                  r.backend.c_str(), r.tolerance, ToString(r.report.status), r.report.residual,
                  r.report.iterations, r.report.seconds, r.force_distance);
    }
    for (std::size_t k = 0; k < problems.size(); ++k) {
      std::printf("reference of %s: %s, residual %.2e\n", problems[k].name.c_str(),
                  refs[k].source.c_str(), refs[k].residual);
    }
  }
  return rc;
}

}  // namespace unjam::cli
