// Benchmark of contact detection: the cell list per particle at growing N (it should stay
// flat, the cost being linear), and the O(N²) reference at N = 1000 for the ratio.
//
//   ./build/bench_broad_phase --benchmark_min_time=0.2
//
// items_per_second is particles per second, so 1 / items_per_second is the time per particle.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "unjam/contacts/contact.hpp"

namespace unjam {
namespace {

// A dense periodic polydisperse configuration: radii uniform in [0.5, 1], centres on a
// square lattice with jitter, packing fraction 0.8. Disks overlap a little, as in a
// compressed packing, which gives a realistic number of contacts per particle.
Scene DenseScene(int n, bool shuffled, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> radius(0.5, 1.0);
  std::uniform_real_distribution<double> jitter(-0.25, 0.25);
  Scene scene;
  scene.cell.periodicity = Periodicity::kXY;
  double area = 0.0;
  for (int i = 0; i < n; ++i) {
    Particle p;
    p.radius = radius(rng);
    area += std::numbers::pi * p.radius * p.radius;
    scene.particles.push_back(p);
  }
  const double side = std::sqrt(area / 0.8);
  scene.cell.size = Vec2(side, side);
  const int columns = static_cast<int>(std::ceil(std::sqrt(n)));
  const double spacing = side / columns;
  for (int i = 0; i < n; ++i) {
    const double x = (i % columns + 0.5 + jitter(rng)) * spacing;
    const double y = (i / columns + 0.5 + jitter(rng)) * spacing;
    scene.particles[i].position = Vec2(x, y);
  }
  // Shuffled indices have no relation to space, as after a long simulation (the worst case
  // for memory access); unshuffled ones follow the lattice rows (the best case).
  if (shuffled) std::shuffle(scene.particles.begin(), scene.particles.end(), rng);
  WrapPositions(scene);
  return scene;
}

template <std::vector<Contact> (*Detect)(const Scene&, double)>
void BM_Detect(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Scene scene = DenseScene(n, state.range(1) != 0, 42);
  const double margin = 1e-6 * MaxRadius(scene);
  std::size_t contacts = 0;
  for (auto _ : state) {
    std::vector<Contact> result = Detect(scene, margin);
    contacts = result.size();
    benchmark::DoNotOptimize(result.data());
  }
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["contacts_per_particle"] = static_cast<double>(contacts) / n;
}

BENCHMARK(BM_Detect<DetectContacts>)
    ->Name("DetectContacts")
    ->ArgNames({"n", "shuffled"})
    ->ArgsProduct({{1000, 4000, 16000, 64000}, {1}})
    ->Args({64000, 0})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Detect<DetectContactsBruteForce>)
    ->Name("DetectContactsBruteForce")
    ->ArgNames({"n", "shuffled"})
    ->Args({1000, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace unjam

BENCHMARK_MAIN();
