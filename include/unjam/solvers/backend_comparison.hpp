// What accuracy costs in time: every backend on every problem at every tolerance, judged
// by the one residual (residual.hpp) and by the distance of its impulses to a tight
// reference solution (docs/accuracy-vs-time.md). Orchestration only: the problems come
// posed, the backends come by name.
#pragma once

#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "unjam/problem/contact_problem.hpp"
#include "unjam/problem/delassus_problem.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

// A body problem (a packing's step) or a stored one in Delassus form (a `.dat` file),
// solved from `guess` (empty: from zero). A backend that refuses the form (kUnsupported)
// appears as such in the runs.
struct ComparisonProblem {
  std::string name;
  std::variant<ContactProblem, DelassusProblem> problem;
  SolverGuess guess;
};

struct ComparisonOptions {
  std::vector<std::string> backends;
  std::vector<double> tolerances;
  SolverOptions solver;  // everything but the tolerance
  // The reference: this backend at this tolerance (its residual is reported; if it misses
  // the tolerance the best impulses seen over all runs serve instead, and the report says so).
  std::string reference_backend = "newton";
  double reference_tolerance = 1e-13;
};

struct ComparisonReference {
  Eigen::VectorXd impulses;
  double residual = 0.0;
  std::string source;  // "newton at 1e-13", or "best run: nsgs at 1e-12"
  double scale = 0.0;  // mean |r_n| of the reference (force distances divide by it)
};

struct ComparisonRun {
  std::string problem, backend;
  double tolerance = 0.0;
  SolveReport report;           // status, iterations, residual, seconds
  double force_distance = 0.0;  // max_k |r_k − r_ref,k| / reference scale
};

// Runs every (problem, backend, tolerance) in that order and calls `on_run` for each run
// once its problem is done (the force distance needs the final reference); returns the
// reference of each problem. Throws std::invalid_argument for an unknown backend.
std::vector<ComparisonReference> CompareBackends(
    const std::vector<ComparisonProblem>& problems, const ComparisonOptions& options,
    const std::function<void(const ComparisonRun&)>& on_run);

}  // namespace unjam
