#include "cli_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace unjam::cli {

void SolverFlags::Register(CLI::App& app) {
  app.add_option("--backend", backend, "contact solver backend")->capture_default_str();
  app.add_option("--tol", options.tolerance, "tolerance on the unjam residual (docs/residual.md)")
      ->capture_default_str();
  app.add_option("--max-iter", max_iterations,
                 "NSGS sweep limit (newton: of its NSGS warm-up; ipopt, nlopt: De Saxce outer "
                 "iterations; lemke: pivots over all its runs)")
      ->capture_default_str();
  app.add_option("--max-seconds", options.time_limit,
                 "wall-clock limit of one solve: at it the backend stops and reports its best "
                 "iterate as not converged (default: none)")
      ->check(Positive());
  app.add_option("--relaxation", options.nsgs.relaxation, "NSGS over-relaxation factor in (0, 2)")
      ->capture_default_str();
  app.add_option("--order", order,
                 "NSGS sweep order: random, forward, symmetric, local (random blocks of "
                 "neighbouring contacts: faster on large packings), height (contacts by height, "
                 "swept up and down in turn: for piles; docs/performance.md)")
      ->capture_default_str();
  app.add_option("--sweep-seed", options.nsgs.seed, "seed of the random sweep order")
      ->capture_default_str();
  app.add_option("--newton-iter", options.newton.max_iterations,
                 "Newton iteration limit (each one a sparse LU)")
      ->capture_default_str();
  app.add_option("--warmup-tol", options.newton.warmup_tolerance,
                 "Newton: NSGS warms up to this residual first")
      ->capture_default_str();
  app.add_flag("--convex-relaxation", options.de_saxce.convex_relaxation,
               "ipopt, nlopt: solve the convex relaxation once (a different model: sliding "
               "contacts separate)");
  app.add_option("--ipopt-iter", options.ipopt.max_iterations,
                 "ipopt: interior-point iterations per convex solve")
      ->capture_default_str();
  app.add_option("--nlopt-algorithm", nlopt_algorithm, "nlopt: lbfgs (bounded L-BFGS) or ccsaq")
      ->capture_default_str();
  app.add_option("--nlopt-eval", options.nlopt.max_evaluations,
                 "nlopt: objective evaluations per convex solve")
      ->capture_default_str();
  app.add_option("--lemke-row-pivots", options.lemke.pivots_per_row,
                 "lemke: pivots per complementarity row that each of its runs may take before the "
                 "next is tried (0: 20, and 200 in the rate form)")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  app.add_flag("--require-converged", require_converged,
               "exit with code 3 if the solver did not converge");
}

SolverOptions SolverFlags::Resolve() const {
  SolverOptions o = options;
  o.SetIterationLimit(max_iterations);
  o.nsgs.order = SweepOrderFromString(order);
  o.nlopt.algorithm = NloptAlgorithmFromString(nlopt_algorithm);
  Validate(o);
  if (!(backend_may_be_auto && backend == "auto"))
    MakeSolver(backend);  // throws for an unknown one, listing the known ones
  return o;
}

namespace {
std::string ShellQuoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

FigureStatus RunPlotScript(const std::string& name, const std::vector<std::string>& args) {
  const std::string python = UNJAM_PYTHON;
  if (python.empty()) return FigureStatus::kSkipped;
  const std::filesystem::path script = std::filesystem::path(UNJAM_SCRIPTS_DIR) / name;
  std::string command = ShellQuoted(python) + " " + ShellQuoted(script.string());
  for (const std::string& a : args) command += " " + ShellQuoted(a);
  command += " >/dev/null";
  return std::system(command.c_str()) == 0 ? FigureStatus::kDrawn : FigureStatus::kFailed;
}

const char* FiguresSkippedReason() { return UNJAM_FIGURES_NOTE; }

int ThreadsFromOption(int requested) {
  return requested > 0 ? requested
                       : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

std::string DefaultPackingPath() {
  const std::filesystem::path local = "problems/pressure-n500-mu0.5.unjam";
  if (std::filesystem::exists(local)) return local.string();
  return (std::filesystem::path(UNJAM_SOURCE_DIR) / local).string();
}

nlohmann::json ToJson(const SolveReport& r) {
  return {{"backend", r.backend},       {"status", ToString(r.status)},
          {"converged", r.converged()}, {"iterations", r.iterations},
          {"residual", r.residual},     {"seconds", r.seconds},
          {"message", r.message}};
}

std::string ExactNumber(double x) { return std::isfinite(x) ? Format("%.17g", x) : ""; }

// FNV-1a of a file (cli_common.hpp).
std::string FileFingerprint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::uint64_t h = 1469598103934665603ull;
  char c;
  while (in.get(c)) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

const char* PeriodicityName(Periodicity p) {
  switch (p) {
    case Periodicity::kNone: return "none";
    case Periodicity::kX: return "x";
    case Periodicity::kXY: return "xy";
  }
  return "?";
}

std::string EffectsSummary(const Scene& s) {
  std::ostringstream os;
  const char* sep = "";
  if (s.effects.gravity) {
    os << sep << "gravity (" << s.effects.gravity->x() << ", " << s.effects.gravity->y() << ")";
    sep = ", ";
  }
  if (s.effects.Frictional()) {
    os << sep << "friction mu=" << s.effects.friction;
    sep = ", ";
  }
  if (s.effects.pressure_bath) {
    os << sep << "pressure bath P=" << s.effects.pressure_bath->pressure;
    sep = ", ";
  }
  if (!s.effects.prescribed_motion.empty()) {
    os << sep << s.effects.prescribed_motion.size() << " prescribed motions";
    sep = ", ";
  }
  if (!s.effects.prescribed_gaps.empty()) {
    os << sep << s.effects.prescribed_gaps.size() << " held gaps";
    sep = ", ";
  }
  if (!s.cell.walls.empty()) {
    os << sep << s.cell.walls.size() << " walls";
    sep = ", ";
  }
  const std::string out = os.str();
  return out.empty() ? "none (frictionless, no load)" : out;
}

std::optional<ShiftSelection> ShiftFlags::Selection() const {
  using Kind = ShiftSelection::Kind;
  if (top) return ShiftSelection{Kind::kTop};
  if (bottom) return ShiftSelection{Kind::kBottom};
  if (down) return ShiftSelection{Kind::kDown, *down};
  if (up) return ShiftSelection{Kind::kUp, *up};
  return std::nullopt;
}

}  // namespace unjam::cli
