// The library's one pool of worker threads: a loop over indices 0 … count − 1 whose answers
// do not depend on the thread count. Each index is computed by the same call whichever
// thread runs it, and the calling thread hears of the indices in index order (or, on
// request, as they finish), so outputs come in the same order on any number of threads.
// Used by the perturbations of an ensemble (protocols/) and the blocks of the force and
// shift bounds (indeterminacy/). NSGS's domain team (src/solvers/nsgs_domains.hpp) is
// another shape: a persistent team that meets at barriers twice per sweep.
#pragma once

#include <functional>

namespace unjam::parallel {

// How ForEachIndex hands out its indices and reports them.
struct Schedule {
  // Worker threads. At most 1: every task on the calling thread, in index order, each
  // reported before the next starts.
  int threads = 1;
  // Report each index as soon as its task has returned, in the order the tasks finish,
  // rather than in index order: a long run can then record each answer the moment it exists.
  bool as_finished = false;
  // Asked before each index is handed out (empty: always yes). Once it says no, no index
  // starts; the tasks under way finish and are reported.
  std::function<bool()> may_start;
};

// `threads` threads, answers in index order, no budget.
inline Schedule OnThreads(int threads) {
  Schedule s;
  s.threads = threads;
  return s;
}

// Runs task(k) for k = 0 … count − 1, handing the indices out in increasing order, and calls
// done(k) on the calling thread after task(k) has returned (index order unless
// as_finished). done(k) may read what task(k) wrote: each index is written by its task
// alone, and read after it.
//
// A task or a done that throws stops the loop: no index starts after it, the tasks under
// way finish and are not reported, every thread is joined, and the first exception is
// rethrown here (rather than ending the process from inside a thread).
void ForEachIndex(int count, const Schedule& schedule, const std::function<void(int)>& task,
                  const std::function<void(int)>& done = {});

}  // namespace unjam::parallel
