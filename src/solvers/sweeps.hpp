// The outer loop of nonlinear Gauss–Seidel, shared by NSGS on body problems (nsgs.cpp) and
// on Delassus-form problems (nsgs_delassus.cpp): sweep orders, the residual check every
// `check_interval` sweeps, and the report. Internal to src/solvers.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "deadline.hpp"
#include "splitmix64.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam::solvers_internal {

template <class It>
void Shuffle(It first, std::uint32_t n, SplitMix64& rng) {
  for (std::uint32_t i = n; i > 1; --i) std::swap(first[i - 1], first[rng.Below(i)]);
}

// kLocal: the blocks of kLocalBlock consecutive positions in a random order, each block in
// its own order, so that the hardware prefetcher streams its rows (a random order inside
// the blocks costs 2.5× more per update once the contacts outgrow the cache).
inline void ShuffleBlocks(SplitMix64& rng, std::vector<std::uint32_t>& order) {
  const std::uint32_t n = static_cast<std::uint32_t>(order.size());
  const std::uint32_t block = kLocalBlock;
  std::vector<std::uint32_t> blocks((n + block - 1) / block);
  std::iota(blocks.begin(), blocks.end(), 0u);
  Shuffle(blocks.begin(), static_cast<std::uint32_t>(blocks.size()), rng);
  std::uint32_t at = 0;
  for (std::uint32_t b : blocks) {
    const std::uint32_t begin = b * block, end = std::min(n, begin + block);
    for (std::uint32_t k = begin; k < end; ++k) order[at + k - begin] = k;
    at += end - begin;
  }
}

inline void NextOrder(SweepOrder kind, int sweep, SplitMix64& rng,
                      std::vector<std::uint32_t>& order) {
  const std::uint32_t n = static_cast<std::uint32_t>(order.size());
  switch (kind) {
    case SweepOrder::kForward: return;
    case SweepOrder::kSymmetric:  // forward, backward, forward, …
    case SweepOrder::kHeight:     // the same over contacts laid out by height
      if (sweep > 0) std::reverse(order.begin(), order.end());
      return;
    case SweepOrder::kRandom: Shuffle(order.begin(), n, rng); return;
    case SweepOrder::kLocal: return ShuffleBlocks(rng, order);
  }
}

// Sweeps until `residual()` meets the tolerance or the sweep limit, checking every
// `check_interval` sweeps; `sweep(index)` performs sweep number `index`, in an order of its
// own. Fills iterations, residual, contact_updates, status and message of `report`.
template <class IndexedSweepFn, class ResidualFn>
void RunIndexedSweeps(int num_contacts, const SolverOptions& o, IndexedSweepFn sweep,
                      ResidualFn residual, SolveReport& report) {
  const Deadline deadline(o.time_limit);
  double current = residual();
  int sweeps = 0;
  while (current > o.tolerance && sweeps < o.nsgs.max_sweeps && !deadline.Passed()) {
    const int batch = std::min(o.nsgs.check_interval, o.nsgs.max_sweeps - sweeps);
    for (int b = 0; b < batch; ++b, ++sweeps) sweep(sweeps);
    report.contact_updates += static_cast<std::int64_t>(batch) * num_contacts;
    current = residual();
    if (!std::isfinite(current)) break;
  }
  report.iterations = sweeps;
  report.residual = current;
  if (!std::isfinite(current)) {
    report.status = SolveStatus::kNumericalFailure;
    report.message = "non-finite impulses (check masses and time step)";
  } else if (current <= o.tolerance) {
    report.status = SolveStatus::kConverged;
  } else {
    report.status = SolveStatus::kIterationLimit;
    report.message = sweeps < o.nsgs.max_sweeps ? TimeLimitMessage(o.time_limit)
                                                : "iteration limit reached before the tolerance";
  }
}

// The same with one order over all contacts (o.nsgs.order, drawn from o.nsgs.seed);
// `sweep(order)` performs one sweep over the contacts in `order`.
template <class SweepFn, class ResidualFn>
void RunSweeps(int num_contacts, const SolverOptions& o, SweepFn sweep, ResidualFn residual,
               SolveReport& report) {
  std::vector<std::uint32_t> order(num_contacts);
  std::iota(order.begin(), order.end(), 0u);
  SplitMix64 rng{o.nsgs.seed};
  auto indexed = [&](int index) {
    NextOrder(o.nsgs.order, index, rng, order);
    sweep(order);
  };
  RunIndexedSweeps(num_contacts, o, indexed, residual, report);
}

}  // namespace unjam::solvers_internal
