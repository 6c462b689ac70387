// One static solve per backend and tolerance: what each backend costs for each accuracy.
//
//   ./build/bench_backends --benchmark_min_time=0.01            # one solve per case
//   ./build/bench_backends --benchmark_filter='n500'            # the N = 500 packings only
//
// Problems: the static steps of the bundled packings problems/pressure-n500-mu0.5.unjam,
// pressure-n500-mu0.unjam and pressure-n3000-mu0.5.unjam (skipped if absent), posed as
// `unjam solve` poses them but from zero impulses (from their stored forces every backend
// would stop at once). Cases: every backend of AvailableBackends() × tolerances 1e-4, 1e-8,
// 1e-12. Counters: residual reached, converged (1/0), iterations (NSGS sweeps; Newton steps;
// outer fixed-point iterations of the convex backends), contacts. A case whose backend
// misses the tolerance still reports its time: the time it took to give up, which is what
// a user pays.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <vector>

#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {
namespace {

// Solved without its guess (the stored forces): from zero.
ContactProblem ColdStaticProblem(const std::string& path) {
  return PoseStaticProblem(ReadPacking(path), {}).assembled.problem;
}

void SolveOnce(benchmark::State& state, const ContactProblem& p, const std::string& backend,
               double tolerance) {
  SolverOptions o;
  o.tolerance = tolerance;
  SolveReport last;
  for (auto _ : state) {
    const SolveResult r = MakeSolver(backend)->Solve(p, o);
    benchmark::DoNotOptimize(r.impulses.data());
    last = r.report;
  }
  state.counters["residual"] = last.residual;
  state.counters["converged"] = last.converged() ? 1 : 0;
  state.counters["iterations"] = last.iterations;
  state.counters["contacts"] = p.NumContacts();
}

void RegisterAll() {
  static std::vector<std::pair<std::string, ContactProblem>> problems;
  for (const char* name : {"pressure-n500-mu0.5", "pressure-n500-mu0", "pressure-n3000-mu0.5"}) {
    const std::string path = std::string(UNJAM_SOURCE_DIR) + "/problems/" + name + ".unjam";
    if (std::filesystem::exists(path)) problems.emplace_back(name, ColdStaticProblem(path));
  }
  for (const auto& [name, problem] : problems) {
    for (const std::string& backend : AvailableBackends()) {
      for (double tol : {1e-4, 1e-8, 1e-12}) {
        const std::string label = "static/" + name + "/" + backend + "/tol:" +
                                  (tol == 1e-4   ? "1e-4"
                                   : tol == 1e-8 ? "1e-8"
                                                 : "1e-12");
        const ContactProblem* p = &problem;
        benchmark::RegisterBenchmark(
            label.c_str(),
            [p, backend, tol](benchmark::State& s) { SolveOnce(s, *p, backend, tol); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
}

}  // namespace
}  // namespace unjam

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  unjam::RegisterAll();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
