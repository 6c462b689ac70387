// NSGS cost per contact update on Delassus-form problems (ũ = W r + q), the form Siconos'
// fc2d_nsgs works on, to compare with its cost on the same files.
//
//   ./build/bench_nsgs_delassus --benchmark_min_time=0.5
//
// Problems: every file of Siconos' 2D collection bundled in problems/siconos/collection/,
// and the bundled 1600-disk pile (problems/gravity-n1600-mu0.1.unjam) in Delassus form (no
// pressure bath, so W stays sparse). A fixed number of sweeps from zero impulses is timed;
// the counter ns_per_update = wall time / (sweeps × contacts), the residual evaluated at
// the start and the end only. Siconos' fc2d_nsgs costs about 21–30 ns per update on these
// files (docs/performance.md).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "sweep_timing.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/siconos_problem.hpp"
#include "unjam/problem/assembly.hpp"
#include "unjam/problem/delassus_problem.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam {
namespace {

const char kCollection[] = UNJAM_SOURCE_DIR "/problems/siconos/collection";
const char kPile[] = UNJAM_SOURCE_DIR "/problems/gravity-n1600-mu0.1.unjam";

std::vector<std::filesystem::path> CollectionFiles() {
  std::vector<std::filesystem::path> files;
  if (!std::filesystem::is_directory(kCollection)) return files;
  for (const auto& entry : std::filesystem::directory_iterator(kCollection)) {
    if (entry.path().extension() == ".dat") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

DelassusProblem PileProblem() {
  const Scene s = ReadPacking(kPile);
  AssemblyOptions o;
  o.dt = 1.0;
  o.closed_gap_tolerance = 1e-9;
  return ToDelassusProblem(AssembleProblem(s, DetectContacts(s, 1e-6), o).problem);
}

void TimeSweeps(benchmark::State& state, const DelassusProblem& p, int sweeps) {
  SolverOptions o;
  o.nsgs.order = state.range(1) == 0 ? SweepOrder::kForward : SweepOrder::kRandom;
  TimeFixedSweeps(state, o, sweeps, p.NumContacts(),
                  [&](ContactSolver& solver, const SolverOptions& options) {
                    return solver.SolveDelassus(p, options);
                  });
  state.counters["w_nonzeros"] = static_cast<double>(p.w.nonZeros());
}

void BM_NsgsDelassusCollection(benchmark::State& state) {
  const std::vector<std::filesystem::path> files = CollectionFiles();
  if (static_cast<std::size_t>(state.range(0)) >= files.size()) {
    state.SkipWithError("no such file in problems/siconos/collection");
    return;
  }
  const std::filesystem::path& file = files[state.range(0)];
  state.SetLabel(file.stem().string());
  const DelassusProblem p = ReadSiconosProblem(file);
  // About 10⁶ updates per run, whatever the size.
  TimeSweeps(state, p, std::max(10, 1000000 / std::max(1, p.NumContacts())));
}

void BM_NsgsDelassusPile1600(benchmark::State& state) {
  if (!std::filesystem::exists(kPile)) {
    state.SkipWithError("problems/gravity-n1600-mu0.1.unjam not found (scripts/make-problems.sh)");
    return;
  }
  TimeSweeps(state, PileProblem(), 100);
}

}  // namespace

// Arguments: the file (collection only), the sweep order (0 forward, as Siconos' default;
// 1 random, unjam's default).
BENCHMARK(BM_NsgsDelassusCollection)
    ->ArgsProduct({benchmark::CreateDenseRange(0, 8, 1), {0, 1}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NsgsDelassusPile1600)->ArgsProduct({{0}, {0, 1}})->Unit(benchmark::kMillisecond);

}  // namespace unjam

BENCHMARK_MAIN();
