// Solving a stored contact problem in Delassus form (another code's `.dat` file, or the
// exported step of a packing): the backend's impulses judged by the unjam residual (the
// one ContactSolver::SolveDelassus computes, whatever the backend claims), and by Siconos'
// own error measure for side-by-side numbers (docs/residual.md).
#pragma once

#include <string>

#include <Eigen/Core>

#include "unjam/problem/delassus_problem.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

struct StoredSolution {
  Eigen::VectorXd impulses;  // (r_n, r_t) per contact
  // The backend's report, whose `residual` is the impulses' (ContactSolver computes it); a
  // backend that claims convergence this residual does not confirm is reported as a
  // numerical failure.
  SolveReport report;
  double siconos_error = 0.0;  // SiconosError (residual.hpp)
};

// Throws std::invalid_argument for an unknown backend, bad options or inconsistent sizes.
StoredSolution SolveStoredProblem(const DelassusProblem& problem, const std::string& backend,
                                  const SolverOptions& options);

}  // namespace unjam
