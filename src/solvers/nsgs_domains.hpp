// Threads for NSGS by domain decomposition (nsgs.cpp). Internal to src/solvers.
//
// Why domains and not colours: a coloured Gauss–Seidel needs a barrier per colour (about
// eight per sweep on a disk packing), and a sweep of 3 000 contacts lasts about 40 µs, so
// the barriers would eat the gain on two cores. Splitting the bodies into one connected
// region per thread needs two barriers per sweep: every thread sweeps the contacts inside
// its region (they share no body with another region's), then one thread sweeps the few
// contacts between regions. Each contact is still solved exactly against the latest values
// of its bodies; only the order of the updates differs from a one-thread sweep.
#pragma once

#include <atomic>
#include <thread>
#include <vector>

namespace unjam::solvers_internal {

// A reusable barrier that spins (the phases it separates last microseconds, shorter than a
// sleeping wait's wake-up), and yields after a while so that an oversubscribed machine
// still makes progress.
class SpinBarrier {
 public:
  explicit SpinBarrier(int parties) : parties_(parties) {}

  void Wait() {
    const unsigned generation = generation_.load(std::memory_order_acquire);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == parties_) {
      arrived_.store(0, std::memory_order_relaxed);
      generation_.fetch_add(1, std::memory_order_acq_rel);
      return;
    }
    for (int spins = 0; generation_.load(std::memory_order_acquire) == generation; ++spins) {
      if (spins >= kSpinsBeforeYield) std::this_thread::yield();
    }
  }

 private:
  static constexpr int kSpinsBeforeYield = 1 << 14;
  const int parties_;
  std::atomic<int> arrived_{0};
  std::atomic<unsigned> generation_{0};
};

// Worker threads 1 … n−1 of a team whose thread 0 is the caller. Each round, the caller's
// Run() releases every worker into work(thread), does work(0) itself, and returns when all
// are done. The destructor releases the workers one last time to let them exit.
template <class WorkFn>
class DomainTeam {
 public:
  DomainTeam(int threads, WorkFn work) : barrier_(threads), work_(work) {
    for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { Serve(t); });
  }
  DomainTeam(const DomainTeam&) = delete;
  DomainTeam& operator=(const DomainTeam&) = delete;
  ~DomainTeam() {
    stop_.store(true, std::memory_order_release);
    barrier_.Wait();
    for (std::thread& w : workers_) w.join();
  }

  void Run() {
    barrier_.Wait();
    work_(0);
    barrier_.Wait();
  }

 private:
  void Serve(int thread) {
    for (;;) {
      barrier_.Wait();
      if (stop_.load(std::memory_order_acquire)) return;
      work_(thread);
      barrier_.Wait();
    }
  }

  SpinBarrier barrier_;
  WorkFn work_;
  std::atomic<bool> stop_{false};
  std::vector<std::thread> workers_;
};

}  // namespace unjam::solvers_internal
