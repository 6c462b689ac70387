// `unjam` with no command: the main job on the bundled default packing (docs/cli.md).
// Static solve, contact openings of a sample of contacts, their admissible-force bounds
// beside them, one table, and a PNG of one displacement field. Every number comes from the
// library; this file only orders the calls and prints.
#include "main_job.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "command_perturb.hpp"
#include "unjam/indeterminacy/force_bounds.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam::cli {

void MainJobFlags::Register(CLI::App& app) {
  app.add_option("--sample", sample, "main job: number of contacts opened")->capture_default_str();
  app.add_option("--seed", seed, "main job: seed of the contact sample")->capture_default_str();
  app.add_option("--out", out, "main job: directory for its table, field and figure")
      ->capture_default_str();
  app.add_option("--threads", threads, "main job: threads of the perturbations (0: all cores)")
      ->check(cli::NonNegative())
      ->capture_default_str();
}

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

struct Row {
  PerturbationTarget target;
  double f_cont = 0.0, f_crit = std::nan(""), delta = std::nan(""), residual = std::nan("");
  PerturbationStatus status = PerturbationStatus::kNotConverged;
  Bound lp_min, lp_max, lp_max_without_friction;
};

StaticSolution SolveDefault(const Scene& scene) {
  StaticSolveOptions o;
  o.solver.tolerance = 1e-10;
  return SolveStatic(scene, o);
}

// LP bounds of each row's contact, in the ensemble of the stored contact geometry.
double AddBounds(const Scene& scene, std::vector<Row>& rows) {
  const EquilibriumSystem system = BuildEquilibriumSystem(scene, {});
  std::vector<int> selected;
  std::vector<int> row_of;
  for (int k = 0; k < static_cast<int>(rows.size()); ++k) {
    const PerturbationTarget& t = rows[k].target;
    const int index = FindContact(system.contacts, t.i, t.j, t.image);
    if (index < 0) continue;
    selected.push_back(index);
    row_of.push_back(k);
  }
  const BoundsReport report =
      ComputeForceBounds(system, selected, StoredForcesOf(system, scene.forces), {});
  if (!report.feasible) std::printf("LP ensemble infeasible: %s\n", report.message.c_str());
  for (std::size_t a = 0; a < report.bounds.size(); ++a) {
    Row& row = rows[row_of[a]];
    row.lp_min = report.bounds[a].min;
    row.lp_max = report.bounds[a].max;
    row.lp_max_without_friction = report.bounds[a].max_without_friction;
  }
  return report.seconds;
}

std::string Cell(double x) {
  return std::isfinite(x) ? Format("%10.5g", x) : Format("%10s", "n/a");
}
std::string Cell(const Bound& b) {
  if (b.ok()) return Format("%10.5g", b.value + 0.0);  // + 0.0: no "-0"
  return Format("%10s", ToString(b.status));
}

void PrintTable(const std::vector<Row>& rows) {
  std::printf("%9s %9s %10s %10s %10s %10s %10s %8s %9s  %s\n", "contact", "(i-j)", "F_cont",
              "F_crit", "LP min", "LP max", "LP f_t=0", "delta", "residual", "status");
  for (const Row& r : rows) {
    std::printf("%9s %10s %s %s %s %s %s %8.3g %9.2e  %s\n", "",
                Format("%d-%d", r.target.i, r.target.j).c_str(), Cell(r.f_cont).c_str(),
                Cell(r.f_crit).c_str(), Cell(r.lp_min).c_str(), Cell(r.lp_max).c_str(),
                Cell(r.lp_max_without_friction).c_str(), r.delta, r.residual, ToString(r.status));
  }
}

std::string TableCsv(const std::vector<Row>& rows) {
  auto bound = [](const Bound& b) { return b.ok() ? Format("%.17g", b.value) : std::string(); };
  std::ostringstream os;
  os << "i,j,image_x,image_y,f_cont,f_crit,lp_min,lp_max,lp_max_without_friction,lp_status_without_"
        "friction,delta,residual,status\n";
  for (const Row& r : rows) {
    os << Format("%d,%d,%d,%d,%.17g,%.17g,", r.target.i, r.target.j, r.target.image[0],
                 r.target.image[1], r.f_cont, r.f_crit)
       << bound(r.lp_min) << ',' << bound(r.lp_max) << ',' << bound(r.lp_max_without_friction)
       << ',' << ToString(r.lp_max_without_friction.status)
       << Format(",%.17g,%.6e,", r.delta, r.residual) << ToString(r.status) << "\n";
  }
  return os.str();
}

// The PNG through scripts/figures/plot_displacement.py (matplotlib).
FigureStatus PlotField(const std::filesystem::path& dir, const PerturbationResult& r, double gap) {
  const std::string title =
      Format("contact %d-%d opened by xi = %.3g: F_crit %.5g, delta %.3g (%s)", r.target.i,
             r.target.j, gap, r.f_crit, r.penetration_depth, ToString(r.status));
  return RunPlotScript("plot_displacement.py",
                       {(dir / "displacement.csv").string(), (dir / "displacement.png").string(),
                        "--gap", Format("%.17g", gap), "--origin", Format("%.17g", r.origin.x()),
                        Format("%.17g", r.origin.y()), "--normal", Format("%.17g", r.axis.x()),
                        Format("%.17g", r.axis.y()), "--title", title});
}

}  // namespace

int RunMainJob(const MainJobFlags& flags) {
  if (flags.sample < 1) throw std::invalid_argument("--sample: need at least 1 contact");
  const auto start = Clock::now();
  const std::string path = DefaultPackingPath();
  const Scene scene = ReadPacking(path);
  std::printf("unjam: main job on the bundled default packing %s\n", path.c_str());
  std::printf(
      "  (%zu particles, %s; the same as `unjam solve`, `unjam perturb --sample %d --seed %llu`, "
      "`unjam bounds`)\n\n",
      scene.particles.size(), EffectsSummary(scene).c_str(), flags.sample,
      static_cast<unsigned long long>(flags.seed));

  auto t = Clock::now();
  const StaticSolution s = SolveDefault(scene);
  const double static_seconds = Since(t);
  const Coordination z = ComputeCoordination(scene, s.contacts, s.forces);
  std::printf(
      "static solve     %s, residual %.2e (%s), %d iterations, z = %.4f, %d rattlers, %.2f s\n",
      s.report.backend.c_str(), s.report.residual,
      s.report.converged() ? "converged" : "NOT converged", s.report.iterations, z.z, z.rattlers,
      static_seconds);

  t = Clock::now();
  PerturbationOptions options;
  ResolveBackends(options, scene);
  const PerturbationBase base = PreparePerturbations(scene, options);
  const std::vector<PerturbationTarget> targets =
      SampleTargets(ContactTargets(base), flags.sample, flags.seed);
  std::vector<Row> rows(targets.size());
  std::optional<PerturbationResult> shown;
  const int threads = ThreadsFromOption(flags.threads);
  PerturbAll(base, targets, options, threads, [&](int k, const PerturbationResult& r) {
    rows[k] = {
        r.target, r.f_reference, r.f_crit, r.penetration_depth, r.solve.residual, r.status, {}, {},
        {}};
    if (!shown || (!shown->ok() && r.ok())) shown = r;  // the first usable response, else the first
  });
  const double perturb_seconds = Since(t);
  std::printf(
      "openings         %zu contacts (gap %.3g, %s, %s), solver tolerance %.2e, %.2f s on %d "
      "threads\n",
      targets.size(), options.gap, ToString(options.cell), options.backend.c_str(),
      SolverToleranceFor(options, base), perturb_seconds, threads);

  const double lp_seconds = AddBounds(scene, rows);
  std::printf("LP bounds        clp, warm starts, %.2f s\n\n", lp_seconds);
  PrintTable(rows);
  std::printf(
      "\nF_crit: force holding the contact open by the gap (docs/perturbations.md); LP min/max: "
      "admissible normal\n"
      "force over all static force networks, LP f_t=0: the largest with no tangential force on the "
      "contact\n"
      "(infeasible: no static network lets this contact open without friction; "
      "docs/indeterminacy.md).\n"
      "status ok: quasi-static response resolved, the same at 10 x the gap; dynamic: the packing "
      "moves (no\n"
      "static F_crit); nonlinear: quasi-static, but another response at 10 x the gap (F_crit "
      "depends on the\n"
      "gap); not-converged: the solver missed the tolerance (see residual); blocked: no motion of "
      "the rigid\n"
      "grains satisfies the step (docs/perturbations.md).\n\n");

  const std::filesystem::path dir = flags.out;
  std::filesystem::create_directories(dir);
  WriteFileAtomically(dir / "main-job.csv", TableCsv(rows));
  int rc = s.report.converged() ? kOk : kNotConverged;
  t = Clock::now();
  WriteFullField(dir, base, *shown);
  switch (PlotField(dir, *shown, options.gap)) {
    case FigureStatus::kDrawn:
      std::printf("figure           %s (contact %d-%d, %s), %.2f s\n",
                  (dir / "displacement.png").c_str(), shown->target.i, shown->target.j,
                  ToString(shown->status), Since(t));
      break;
    case FigureStatus::kSkipped:
      std::printf("figure           skipped: %s\n", FiguresSkippedReason());
      break;
    case FigureStatus::kFailed:
      std::fprintf(stderr,
                   "unjam: error: the figure was not written (%s "
                   "scripts/figures/plot_displacement.py failed)\n",
                   UNJAM_PYTHON);
      rc = kInternalError;
      break;
  }
  std::printf(
      "written          %s: main-job.csv, displacement.csv, response.vtk (ParaView), response.xyz "
      "(OVITO)\n",
      dir.c_str());
  std::printf("total            %.2f s\n", Since(start));
  return rc;
}

}  // namespace unjam::cli
