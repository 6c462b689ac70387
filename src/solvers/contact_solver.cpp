// The one entry point of every backend (contact_solver.hpp): checks, timing and residual
// in one place, so that each backend implements only its method.
#include "unjam/solvers/contact_solver.hpp"

#include <chrono>
#include <stdexcept>

#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

// Runs `solve` and records its wall time and the residual of its impulses: a backend's
// own claim is never what a caller reads.
template <class Problem, class SolveFn>
SolveResult TimedAndJudged(const Problem& problem, const std::string& backend, SolveFn solve) {
  const auto start = std::chrono::steady_clock::now();
  SolveResult result = solve();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (result.impulses.size() != problem.NumUnknowns()) {
    throw std::logic_error("backend '" + backend + "' returned " +
                           std::to_string(result.impulses.size()) + " impulses for " +
                           std::to_string(problem.NumUnknowns()) + " unknowns");
  }
  result.report.residual = ComputeResidual(problem, result.impulses).residual;
  result.report.seconds = seconds;
  return result;
}

}  // namespace

SolveResult ContactSolver::Solve(const ContactProblem& problem, const SolverOptions& options) {
  Validate(problem);
  Validate(options);
  return TimedAndJudged(problem, Name(), [&] { return DoSolve(problem, options); });
}

SolveResult ContactSolver::SolveDelassus(const DelassusProblem& problem,
                                         const SolverOptions& options) {
  Validate(problem);
  Validate(options);
  return TimedAndJudged(problem, Name(), [&] { return DoSolveDelassus(problem, options); });
}

SolveResult ContactSolver::DoSolveDelassus(const DelassusProblem& problem, const SolverOptions&) {
  SolveResult result;
  result.impulses = Eigen::VectorXd::Zero(problem.NumUnknowns());
  result.report.backend = Name();
  result.report.status = SolveStatus::kUnsupported;
  result.report.message =
      "backend '" + Name() +
      "' solves body problems only, not Delassus-form (W, q) problems (docs/backends.md)";
  return result;
}

}  // namespace unjam
