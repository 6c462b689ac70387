#include "unjam/solvers/backend_comparison.hpp"

#include <cmath>
#include <cstdio>

namespace unjam {

namespace {

using AnyProblem = std::variant<ContactProblem, DelassusProblem>;

SolveResult SolveAny(ContactSolver& solver, const ComparisonProblem& cp, const SolverOptions& o) {
  if (const auto* body = std::get_if<ContactProblem>(&cp.problem))
    return solver.Solve(*body, o, cp.guess);
  return solver.SolveDelassus(std::get<DelassusProblem>(cp.problem), o, cp.guess);
}

double MeanNormalImpulse(const AnyProblem& p, const Eigen::VectorXd& r) {
  const int m = std::holds_alternative<ContactProblem>(p)
                    ? std::get<ContactProblem>(p).UnknownsPerContact()
                    : 2;
  const int contacts = static_cast<int>(r.size()) / m;
  double sum = 0.0;
  for (int k = 0; k < contacts; ++k) sum += std::abs(r[k * m]);
  return contacts > 0 ? sum / contacts : 0.0;
}

double ForceDistance(const ComparisonReference& ref, const Eigen::VectorXd& r) {
  if (r.size() != ref.impulses.size() || r.size() == 0) return std::nan("");
  const double d = (r - ref.impulses).cwiseAbs().maxCoeff();
  return ref.scale > 0.0 ? d / ref.scale : d;
}

std::string Describe(const std::string& backend, double tolerance) {
  char buf[64];
  std::snprintf(buf, sizeof buf, " at %.0e", tolerance);
  return backend + buf;
}

}  // namespace

std::vector<ComparisonReference> CompareBackends(
    const std::vector<ComparisonProblem>& problems, const ComparisonOptions& options,
    const std::function<void(const ComparisonRun&)>& on_run) {
  for (const std::string& b : options.backends) MakeSolver(b);  // unknown names fail first
  std::vector<ComparisonReference> references;
  for (const ComparisonProblem& cp : problems) {
    SolverOptions tight = options.solver;
    tight.tolerance = options.reference_tolerance;
    const SolveResult ref = SolveAny(*MakeSolver(options.reference_backend), cp, tight);
    ComparisonReference reference{ref.impulses, ref.report.residual,
                                  Describe(options.reference_backend, options.reference_tolerance),
                                  0.0};
    if (!ref.report.converged()) reference.source += " (not reached)";

    std::vector<ComparisonRun> runs;
    std::vector<Eigen::VectorXd> impulses;
    for (const std::string& backend : options.backends) {
      for (double tolerance : options.tolerances) {
        SolverOptions o = options.solver;
        o.tolerance = tolerance;
        SolveResult s = SolveAny(*MakeSolver(backend), cp, o);
        runs.push_back({cp.name, backend, tolerance, s.report, 0.0});
        impulses.push_back(std::move(s.impulses));
        if (s.report.status != SolveStatus::kUnsupported &&
            s.report.residual < reference.residual) {  // a better solution than the reference run
          reference = {impulses.back(), s.report.residual,
                       "best run: " + Describe(backend, tolerance), 0.0};
        }
      }
    }
    reference.scale = MeanNormalImpulse(cp.problem, reference.impulses);
    for (std::size_t k = 0; k < runs.size(); ++k) {
      runs[k].force_distance = ForceDistance(reference, impulses[k]);
      on_run(runs[k]);
    }
    references.push_back(std::move(reference));
  }
  return references;
}

}  // namespace unjam
