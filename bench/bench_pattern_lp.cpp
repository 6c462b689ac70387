// The pattern LP (solvers/pattern_lp.hpp, `perturb --member nearest`) against the backend
// whose answer it starts from: one quasi-static opening of the default packing and one top
// shift of the small pile, each solved first by lemke (outside the timing), then timed:
//
//   ./build/bench_pattern_lp --benchmark_min_time=0.01
//
// Cases: `lemke/…` the lemke solve itself, `pattern/…` the pattern LP from its answer.
// Counters: residual of the answer, found (1/0), contacts, simplex iterations.
#include <benchmark/benchmark.h>

#include <string>
#include <utility>

#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/perturbation.hpp"
#include "unjam/solvers/pattern_lp.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {
namespace {

struct Case {
  ContactProblem problem;
  SolverGuess guess;  // the static forces' impulses
  SolverOptions options;
};

Case Pose(const std::string& file, bool top_shift, int index) {
  const Scene scene = ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/" + file);
  PerturbationOptions o;
  const PerturbationBase base = PreparePerturbations(scene, o);
  const std::vector<PerturbationTarget> targets =
      top_shift ? TopTargets(base) : SampleTargets(ContactTargets(base), 10, 1);
  StaticProblem posed = PosePerturbationProblem(base, targets[index], o);
  Case c{std::move(posed.assembled.problem), std::move(posed.guess), o.solver};
  c.options.tolerance = SolverToleranceFor(o, base);
  c.options.lemke.velocity_scale = o.gap / o.dt;
  return c;
}

// Opening 49–252 of the default packing (651 contacts) and the shift of particle 33 of the
// small pile (164 contacts): both quasi-static, both answers replaced by another member.
const Case& Opening() {
  static const Case c = Pose("pressure-n500-mu0.5.unjam", false, 1);
  return c;
}
const Case& Shift() {
  static const Case c = Pose("gravity-n100-mu0.5.unjam", true, 5);
  return c;
}

void Lemke(benchmark::State& state, const Case& (*make)()) {
  const Case& c = make();
  SolveReport last;
  for (auto _ : state) {
    const SolveResult r = MakeSolver("lemke")->Solve(c.problem, c.options, c.guess);
    benchmark::DoNotOptimize(r.impulses.data());
    last = r.report;
  }
  state.counters["residual"] = last.residual;
  state.counters["contacts"] = c.problem.NumContacts();
}

void Pattern(benchmark::State& state, const Case& (*make)()) {
  const Case& c = make();
  const SolveResult start = MakeSolver("lemke")->Solve(c.problem, c.options, c.guess);
  PatternSolution last;
  for (auto _ : state) {
    last = SolveOnPattern(c.problem, start.impulses, c.guess.impulses,
                          c.options.lemke.velocity_scale, 1.0);
    benchmark::DoNotOptimize(last.impulses.data());
  }
  state.counters["found"] = last.found ? 1 : 0;
  state.counters["residual"] =
      last.found ? ComputeResidual(c.problem, last.impulses).residual : 0.0;
  state.counters["contacts"] = c.problem.NumContacts();
  state.counters["simplex_iterations"] = static_cast<double>(last.iterations);
}

BENCHMARK_CAPTURE(Lemke, opening_n500_mu0_5, &Opening)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Pattern, opening_n500_mu0_5, &Opening)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Lemke, top_shift_pile_n100, &Shift)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Pattern, top_shift_pile_n100, &Shift)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace unjam

BENCHMARK_MAIN();
