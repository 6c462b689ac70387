// NSGS's cost per contact update, timed over a fixed number of sweeps: shared by the
// benchmarks of the body form (bench_nsgs.cpp) and the Delassus form (bench_nsgs_delassus.cpp).
#pragma once

#include <benchmark/benchmark.h>

#include <cstdint>

#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

// Runs solve(solver, options) once per benchmark iteration with `options` set to stop after
// exactly `sweeps` sweeps (a tolerance never reached, the residual checked at the start and
// the end only); counters `contacts` and ns_per_update = wall time / (sweeps × contacts).
template <class Solve>
void TimeFixedSweeps(benchmark::State& state, SolverOptions options, int sweeps, int contacts,
                     Solve solve) {
  options.tolerance = 1e-300;
  options.nsgs.max_sweeps = sweeps;
  options.nsgs.check_interval = sweeps;
  auto solver = MakeSolver("nsgs");
  std::int64_t updates = 0;
  double seconds = 0.0;
  for (auto _ : state) {
    SolveResult r = solve(*solver, options);
    updates += r.report.contact_updates;
    seconds += r.report.seconds;
    benchmark::DoNotOptimize(r.impulses.data());
  }
  state.counters["contacts"] = contacts;
  state.counters["ns_per_update"] = seconds * 1e9 / static_cast<double>(updates);
  state.SetItemsProcessed(updates);
}

}  // namespace unjam
