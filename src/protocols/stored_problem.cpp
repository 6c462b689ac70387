#include "unjam/protocols/stored_problem.hpp"

#include <cstdio>

#include "unjam/solvers/residual.hpp"

namespace unjam {

StoredSolution SolveStoredProblem(const DelassusProblem& problem, const std::string& backend,
                                  const SolverOptions& options) {
  SolveResult result = MakeSolver(backend)->SolveDelassus(problem, options);
  StoredSolution out;
  out.impulses = std::move(result.impulses);
  out.report = std::move(result.report);  // its residual is the one of out.impulses
  if (out.report.converged() && !(out.report.residual <= options.tolerance)) {
    char message[160];
    std::snprintf(message, sizeof message,
                  "the backend reported convergence, but the residual of its impulses is %.3e",
                  out.report.residual);
    out.report.status = SolveStatus::kNumericalFailure;
    out.report.message = message;
  }
  out.siconos_error = SiconosError(problem, out.impulses);
  return out;
}

}  // namespace unjam
