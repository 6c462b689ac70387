// NSGS cost per contact update, and what friction adds to it.
//
//   ./build/bench_nsgs --benchmark_min_time=0.5
//
// Problems: (1) the static solve of the bundled jammed packing
// problems/pressure-n3000-mu0.5.unjam (skipped if absent), with its own μ = 0.5 and with
// μ = 0; (2) a dense periodic packing of 56 × 56 = 3136 disks under a pressure bath (a
// triangular lattice whose radii are shrunk at random by up to 0.1%: a disordered contact
// network of about 9400 contacts), and (3) the same lattice from 56² to 160² disks, to see
// where the contacts outgrow the cache; (4) the bundled pile problems/gravity-n1600-mu0.1.unjam
// under gravity, swept at random or by height. The counter ns_per_update = wall time /
// (sweeps × contacts); a fixed number of sweeps is timed, the residual evaluated at the
// start and end. BM_NsgsPileFromRest instead solves the pile's static step from zero
// impulses to a tolerance and counts the sweeps it takes (counter `sweeps`).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include <filesystem>
#include <string>

#include "sweep_timing.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/problem/assembly.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {
namespace {

ContactProblem DenseProblem(double mu, int side) {
  const double r = 0.5;
  const double dy = std::sqrt(3.0) * r;
  Scene s;
  s.cell.size = Vec2(2.0 * r * side, dy * side);
  s.cell.periodicity = Periodicity::kXY;
  s.effects.friction = mu;
  s.effects.pressure_bath = PressureBath{1.0, 100.0, 0.0};
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> shrink(0.0, 1e-3);
  for (int row = 0; row < side; ++row) {
    for (int col = 0; col < side; ++col) {
      Particle p;
      p.radius = r * (1.0 - shrink(rng));
      p.position = Vec2(2.0 * r * col + (row % 2 ? r : 0.0) + 0.5 * r, dy * (row + 0.5));
      s.particles.push_back(p);
    }
  }
  AssemblyOptions o;
  o.dt = 1.0;
  return AssembleProblem(s, DetectContacts(s, 1e-2), o).problem;
}

const char kJammed[] = UNJAM_SOURCE_DIR "/problems/pressure-n3000-mu0.5.unjam";
const char kPile[] = UNJAM_SOURCE_DIR "/problems/gravity-n1600-mu0.1.unjam";

ContactProblem StoredProblem(const char* path, double mu) {
  Scene s = ReadPacking(path);
  s.effects.friction = mu;
  AssemblyOptions o;
  o.dt = 1.0;
  o.closed_gap_tolerance = 1e-9;
  return AssembleProblem(s, DetectContacts(s, 1e-6), o).problem;
}

ContactProblem JammedProblem(double mu) { return StoredProblem(kJammed, mu); }

// A bundled problem file, or the benchmark is skipped with the command that makes it.
bool Bundled(benchmark::State& state, const char* path) {
  if (std::filesystem::exists(path)) return true;
  state.SkipWithError((std::string(path) + " not found (scripts/make-problems.sh)").c_str());
  return false;
}

// The benchmarks' sweep-order argument: 0 forward, 1 random, 2 local, 3 height.
constexpr SweepOrder kOrders[] = {SweepOrder::kForward, SweepOrder::kRandom, SweepOrder::kLocal,
                                  SweepOrder::kHeight};

void TimeSweeps(benchmark::State& state, const ContactProblem& p, int threads = 1) {
  SolverOptions o;
  o.nsgs.threads = threads;
  o.nsgs.order = kOrders[state.range(1)];
  TimeFixedSweeps(state, o, 100, p.NumContacts(),
                  [&](ContactSolver& solver, const SolverOptions& options) {
                    return solver.Solve(p, options);
                  });
}

void BM_NsgsSweeps(benchmark::State& state) {
  TimeSweeps(state, DenseProblem(state.range(0) / 100.0, 56));
}

void BM_NsgsSweepsJammed3000(benchmark::State& state) {
  if (!Bundled(state, kJammed)) return;
  TimeSweeps(state, JammedProblem(state.range(0) / 100.0));
}

void BM_NsgsSweepsPile1600(benchmark::State& state) {
  if (!Bundled(state, kPile)) return;
  TimeSweeps(state, StoredProblem(kPile, state.range(0) / 100.0));
}

// Sweeps on range(2) threads (nsgs_domains.hpp): the wall time per contact update.
void BM_NsgsThreadsJammed3000(benchmark::State& state) {
  if (!Bundled(state, kJammed)) return;
  TimeSweeps(state, JammedProblem(state.range(0) / 100.0), static_cast<int>(state.range(2)));
}

void BM_NsgsThreadsPile1600(benchmark::State& state) {
  if (!Bundled(state, kPile)) return;
  TimeSweeps(state, StoredProblem(kPile, state.range(0) / 100.0), static_cast<int>(state.range(2)));
}

// Sweeps from zero impulses to residual 10^-range(2) (the limit 10^6 sweeps), on range(3)
// threads.
void BM_NsgsPileFromRest(benchmark::State& state) {
  if (!Bundled(state, kPile)) return;
  const ContactProblem p = StoredProblem(kPile, state.range(0) / 100.0);
  SolverOptions o;
  o.tolerance = std::pow(10.0, -static_cast<double>(state.range(2)));
  o.nsgs.max_sweeps = 1000000;
  o.nsgs.order = kOrders[state.range(1)];
  o.nsgs.threads = state.range(3);
  auto solver = MakeSolver("nsgs");
  SolveResult r;
  for (auto _ : state) {
    r = solver->Solve(p, o);
    benchmark::DoNotOptimize(r.impulses.data());
  }
  state.counters["sweeps"] = r.report.iterations;
  state.counters["residual"] = r.report.residual;
  state.counters["ns_per_update"] =
      r.report.seconds * 1e9 / static_cast<double>(r.report.contact_updates);
}

// The lattice with side² disks: from N = 3136 (9 400 contacts, which fit in the core's
// cache) to N = 25 600 (77 000 contacts, which do not).
void BM_NsgsSweepsBySize(benchmark::State& state) {
  TimeSweeps(state, DenseProblem(state.range(0) / 100.0, static_cast<int>(state.range(2))));
}

// Args: μ × 100, sweep order (0 forward, 1 random, 2 local, 3 height)[, lattice side, or
// −log10 of the tolerance].
BENCHMARK(BM_NsgsSweepsJammed3000)
    ->Args({50, 1})
    ->Args({0, 1})
    ->Args({50, 2})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NsgsSweeps)
    ->Args({0, 1})
    ->Args({50, 1})
    ->Args({0, 0})
    ->Args({50, 0})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NsgsSweepsPile1600)
    ->Args({10, 1})
    ->Args({10, 3})
    ->Args({10, 0})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NsgsPileFromRest)
    ->Args({10, 1, 4, 1})
    ->Args({10, 3, 4, 1})
    ->Args({10, 0, 4, 1})
    ->Args({10, 1, 4, 2})
    ->Args({10, 3, 4, 2})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_NsgsThreadsJammed3000)
    ->Args({50, 1, 1})
    ->Args({50, 1, 2})
    ->Args({50, 3, 1})
    ->Args({50, 3, 2})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NsgsThreadsPile1600)
    ->Args({10, 3, 1})
    ->Args({10, 3, 2})
    ->Args({10, 1, 2})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NsgsSweepsBySize)
    ->Args({50, 1, 56})
    ->Args({50, 1, 80})
    ->Args({50, 1, 112})
    ->Args({50, 1, 160})
    ->Args({50, 2, 56})
    ->Args({50, 2, 80})
    ->Args({50, 2, 112})
    ->Args({50, 2, 160})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace unjam

BENCHMARK_MAIN();
