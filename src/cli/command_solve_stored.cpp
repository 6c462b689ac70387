// `unjam solve PROBLEM.dat`: a stored 2D friction-contact problem (Siconos numerics format)
// solved by any backend, judged by the unjam residual and by Siconos' own error measure.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "command_solve.hpp"
#include "unjam/io/siconos_problem.hpp"
#include "unjam/protocols/stored_problem.hpp"

namespace unjam::cli {

namespace {

void PrintTable(const std::string& path, const DelassusProblem& p, const StoredSolution& s) {
  const SolveReport& r = s.report;
  std::printf("backend           %s\n", r.backend.c_str());
  std::printf("problem           %s (Siconos 2D friction contact)\n", path.c_str());
  std::printf("contacts          %d (%d unknowns)\n", p.NumContacts(), p.NumUnknowns());
  std::printf("iterations        %d\n", r.iterations);
  std::printf("residual          %.3e (unjam: worst contact / mean normal impulse)\n", r.residual);
  std::printf("siconos error     %.3e (Siconos fc2d: |natural map| / max(|r|, |u|, |q|))\n",
              s.siconos_error);
  std::printf("converged         %s%s%s\n", r.converged() ? "yes" : "NO",
              r.message.empty() ? "" : ": ", r.message.c_str());
  std::printf("seconds           %.3f\n", r.seconds);
}

void PrintImpulses(const Eigen::VectorXd& r) {
  std::printf("\n%8s %22s %22s\n", "contact", "r_n", "r_t");
  for (Eigen::Index k = 0; k < r.size() / 2; ++k) {
    std::printf("%8ld %22.15e %22.15e\n", static_cast<long>(k), r[2 * k], r[2 * k + 1]);
  }
}

nlohmann::json Json(const SolveFlags& flags, const DelassusProblem& p, const StoredSolution& s) {
  nlohmann::json out = ToJson(s.report);
  out["file"] = flags.file;
  out["format"] = "siconos";
  out["contacts"] = p.NumContacts();
  out["unknowns"] = p.NumUnknowns();
  out["siconos_error"] = NumberOrNull(s.siconos_error);
  out["residual"] = NumberOrNull(s.report.residual);
  if (!flags.output.empty()) out["output"] = flags.output;
  if (!flags.export_problem.empty()) out["exported_problem"] = flags.export_problem;
  if (flags.forces) {
    nlohmann::json impulses = nlohmann::json::array();
    for (Eigen::Index k = 0; k < s.impulses.size() / 2; ++k) {
      impulses.push_back({NumberOrNull(s.impulses[2 * k]), NumberOrNull(s.impulses[2 * k + 1])});
    }
    out["impulses"] = impulses;
  }
  return out;
}

}  // namespace

bool IsSiconosFile(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension == ".dat";
}

int RunSolveStored(const SolveFlags& flags) {
  const DelassusProblem problem = ReadSiconosProblem(flags.file);
  const SolverOptions options = flags.solver.Resolve();
  const StoredSolution s = SolveStoredProblem(problem, flags.solver.backend, options);
  // A backend that cannot take the W form is a wrong choice, not a failed solve: nothing
  // is written.
  if (s.report.status == SolveStatus::kUnsupported) throw std::invalid_argument(s.report.message);
  if (!flags.export_problem.empty()) WriteSiconosProblem(problem, flags.export_problem);
  if (!flags.output.empty()) WriteImpulses(s.impulses, flags.output);
  if (flags.json) {
    std::printf("%s\n", Json(flags, problem, s).dump().c_str());
  } else {
    PrintTable(flags.file, problem, s);
    if (flags.forces) PrintImpulses(s.impulses);
  }
  if (!s.report.converged()) {
    std::fprintf(stderr,
                 "unjam solve: the solver did not converge (%s, residual %.3e > tolerance %.3e)\n",
                 ToString(s.report.status), s.report.residual, options.tolerance);
    if (flags.solver.require_converged) return kNotConverged;
  }
  return kOk;
}

}  // namespace unjam::cli
