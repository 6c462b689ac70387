// The pattern solve that ends every static solve (solvers/pattern_polish.hpp): an NSGS
// answer of 3 000 sweeps from zero impulses (outside the timing), solved on its own pattern
// with up to 20 rounds of corrections (fewer once 4 rounds bring no better answer), each one
// sparse LU factorisation (UMFPACK):
//
//   ./build/bench_pattern_solve --benchmark_min_time=0.01
//
// Counters: contacts, degrees of freedom plus impulse components (the size of the system when
// every contact sticks), the residual before and after.
#include <benchmark/benchmark.h>

#include <string>
#include <utility>

#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/static_solve.hpp"
#include "unjam/solvers/contact_solver.hpp"
#include "unjam/solvers/pattern_polish.hpp"

namespace unjam {
namespace {

struct Case {
  ContactProblem problem;
  SolveResult start;
};

Case Pose(const std::string& file) {
  const Scene scene = ReadPacking(std::string(UNJAM_SOURCE_DIR) + "/problems/" + file);
  StaticSolveOptions o;
  StaticProblem posed = PoseStaticProblem(scene, o);
  SolverOptions nsgs;
  nsgs.tolerance = 1e-12;
  nsgs.SetIterationLimit(3000);
  Case c{std::move(posed.assembled.problem), {}};
  c.start = MakeSolver("nsgs")->Solve(c.problem, nsgs);  // from zero impulses
  return c;
}

const Case& Cell() {
  static const Case c = Pose("pressure-n3000-mu0.5.unjam");
  return c;
}
const Case& Pile() {
  static const Case c = Pose("gravity-n1600-mu0.1.unjam");
  return c;
}

void Polish(benchmark::State& state, const Case& (*make)()) {
  const Case& c = make();
  SolveResult last;
  for (auto _ : state) {
    last = PolishOnPattern(c.problem, c.start, 1e-12);
    benchmark::DoNotOptimize(last.impulses.data());
  }
  state.counters["contacts"] = c.problem.NumContacts();
  state.counters["dofs_and_impulses"] = c.problem.NumDofs() + c.problem.NumUnknowns();
  state.counters["residual_before"] = c.start.report.residual;
  state.counters["residual_after"] = last.report.residual;
}

BENCHMARK_CAPTURE(Polish, cell_n3000_mu0_5, &Cell)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(Polish, pile_n1600_mu0_1, &Pile)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace unjam

BENCHMARK_MAIN();
