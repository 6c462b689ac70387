#include "unjam/parallel/for_each_index.hpp"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace unjam::parallel {

namespace {

// What the workers and the calling thread share, each field under `mutex`.
struct Progress {
  explicit Progress(int count) : finished(std::max(count, 0), 0) {}
  std::mutex mutex;
  std::condition_variable changed;
  int started = 0;
  bool closed = false;  // no index starts any more: all handed out, budget spent, or failure
  std::exception_ptr failure;
  std::vector<char> finished;        // per index: its task has returned
  std::deque<int> finish_order;      // finished, not yet reported, in the order they finished
  void Fail(std::exception_ptr e) {  // the first failure wins; the caller holds the mutex
    if (!failure) failure = e;
    closed = true;
  }
};

void RunOnThisThread(int count, const Schedule& schedule, const std::function<void(int)>& task,
                     const std::function<void(int)>& done) {
  for (int k = 0; k < count && (!schedule.may_start || schedule.may_start()); ++k) {
    task(k);
    if (done) done(k);
  }
}

// A worker: takes the next index until none is left, the budget is spent or a task failed.
void Work(int count, const Schedule& schedule, const std::function<void(int)>& task, Progress& p) {
  for (;;) {
    int k = 0;
    {
      std::lock_guard<std::mutex> lock(p.mutex);
      if (p.closed || p.started == count || (schedule.may_start && !schedule.may_start())) {
        p.closed = true;
        p.changed.notify_all();
        return;
      }
      k = p.started++;
    }
    std::exception_ptr failure;
    try {
      task(k);
    } catch (...) {
      failure = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(p.mutex);
    if (failure) {
      p.Fail(failure);
    } else {
      p.finished[k] = 1;
      p.finish_order.push_back(k);
    }
    p.changed.notify_all();
  }
}

// The calling thread: reports each finished index, in index order or as they finished,
// until every started one is reported or something failed.
void Report(int count, const Schedule& schedule, const std::function<void(int)>& done,
            Progress& p) {
  for (int reported = 0;; ++reported) {
    std::unique_lock<std::mutex> lock(p.mutex);
    auto next_ready = [&] {
      return reported < count &&
             (schedule.as_finished ? !p.finish_order.empty() : p.finished[reported] != 0);
    };
    p.changed.wait(
        lock, [&] { return p.failure || (p.closed && reported == p.started) || next_ready(); });
    if (p.failure || !next_ready()) return;
    const int k = schedule.as_finished ? p.finish_order.front() : reported;
    if (schedule.as_finished) p.finish_order.pop_front();
    lock.unlock();
    try {
      if (done) done(k);
    } catch (...) {
      // The caller could not take the answer (e.g. its records file): stop the workers
      // after the tasks they are running, and pass the error on.
      std::lock_guard<std::mutex> relock(p.mutex);
      p.Fail(std::current_exception());
      return;
    }
  }
}

}  // namespace

void ForEachIndex(int count, const Schedule& schedule, const std::function<void(int)>& task,
                  const std::function<void(int)>& done) {
  if (schedule.threads <= 1) {
    RunOnThisThread(count, schedule, task, done);
    return;
  }
  Progress progress(count);
  std::vector<std::thread> workers;
  for (int t = 0; t < schedule.threads; ++t)
    workers.emplace_back([&] { Work(count, schedule, task, progress); });
  Report(count, schedule, done, progress);
  for (std::thread& w : workers) w.join();
  if (progress.failure) std::rethrow_exception(progress.failure);
}

}  // namespace unjam::parallel
