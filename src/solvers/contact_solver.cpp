// The one entry point of every backend (contact_solver.hpp): checks, timing and residual
// in one place, so that each backend implements only its method.
#include "unjam/solvers/contact_solver.hpp"

#include <chrono>
#include <stdexcept>

#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

void RequireEmptyOrSize(const char* field, std::size_t size, std::size_t expected,
                        const char* per) {
  if (size == 0 || size == expected) return;
  throw std::invalid_argument("solver guess: " + std::string(field) + " has " +
                              std::to_string(size) + " entries, expected " +
                              std::to_string(expected) + " (" + per + ") or 0");
}

// A guess of another size is a caller's mix-up (another problem's impulses), not a cold
// start: it is refused rather than ignored.
template <class Problem>
void ValidateGuess(const Problem& problem, const SolverGuess& guess) {
  RequireEmptyOrSize("guess.impulses", static_cast<std::size_t>(guess.impulses.size()),
                     static_cast<std::size_t>(problem.NumUnknowns()), "one per unknown");
  RequireEmptyOrSize("guess.basis", guess.basis.size(),
                     static_cast<std::size_t>(problem.NumContacts()), "one per contact");
}

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

SolveResult ContactSolver::Solve(const ContactProblem& problem, const SolverOptions& options,
                                 const SolverGuess& guess) {
  Validate(problem);
  Validate(options);
  ValidateGuess(problem, guess);
  return TimedAndJudged(problem, Name(), [&] { return DoSolve(problem, options, guess); });
}

SolveResult ContactSolver::SolveDelassus(const DelassusProblem& problem,
                                         const SolverOptions& options, const SolverGuess& guess) {
  Validate(problem);
  Validate(options);
  ValidateGuess(problem, guess);
  return TimedAndJudged(problem, Name(), [&] { return DoSolveDelassus(problem, options, guess); });
}

SolveResult ContactSolver::DoSolveDelassus(const DelassusProblem& problem, const SolverOptions&,
                                           const SolverGuess&) {
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
