// The thread pool's promises: every index once, answers reported in index order (or each
// once as they finish) whatever the thread count, a budget that stops new indices, and
// errors of a task or of the caller passed on after the threads are joined.
#include "unjam/parallel/for_each_index.hpp"

#include <atomic>
#include <chrono>
#include <map>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace unjam::parallel {
namespace {

// A task whose time varies with k, so that threads finish out of index order.
long long SlowSquare(int k) {
  std::this_thread::sleep_for(std::chrono::microseconds(200 * ((k * 7) % 5)));
  return static_cast<long long>(k) * k;
}

TEST(ForEachIndex, ReportsInIndexOrderWhateverTheThreadCount) {
  constexpr int kCount = 40;
  for (const int threads : {0, 1, 2, 4, 7}) {
    std::vector<long long> answers(kCount, -1);
    std::vector<int> order;
    std::vector<long long> reported;
    ForEachIndex(
        kCount, OnThreads(threads), [&](int k) { answers[k] = SlowSquare(k); },
        [&](int k) {
          order.push_back(k);
          reported.push_back(answers[k]);  // written by the task, read here
        });
    ASSERT_EQ(order.size(), static_cast<std::size_t>(kCount)) << threads << " threads";
    for (int k = 0; k < kCount; ++k) {
      EXPECT_EQ(order[k], k) << threads << " threads";
      EXPECT_EQ(reported[k], static_cast<long long>(k) * k) << threads << " threads";
    }
  }
}

TEST(ForEachIndex, AsFinishedReportsEveryIndexOnce) {
  constexpr int kCount = 30;
  for (const int threads : {1, 3}) {
    std::vector<long long> answers(kCount, -1);
    std::map<int, long long> reported;
    Schedule schedule = OnThreads(threads);
    schedule.as_finished = true;
    ForEachIndex(
        kCount, schedule, [&](int k) { answers[k] = SlowSquare(k); },
        [&](int k) { EXPECT_TRUE(reported.emplace(k, answers[k]).second) << k << " twice"; });
    ASSERT_EQ(reported.size(), static_cast<std::size_t>(kCount));
    for (const auto& [k, answer] : reported) EXPECT_EQ(answer, static_cast<long long>(k) * k);
  }
}

TEST(ForEachIndex, NoIndexStartsOnceTheBudgetIsSpent) {
  for (const int threads : {1, 3}) {
    std::atomic<int> ran{0};
    Schedule schedule = OnThreads(threads);
    schedule.may_start = [&] { return ran.load() < 2; };
    ForEachIndex(10, schedule, [&](int) { ++ran; });
    // Threads may each pass the check before either task has run: at most one per thread.
    EXPECT_GE(ran.load(), 2) << threads << " threads";
    EXPECT_LE(ran.load(), 1 + threads) << threads << " threads";
    schedule.may_start = [] { return false; };
    int none = 0;
    ForEachIndex(10, schedule, [&](int) { ++none; });
    EXPECT_EQ(none, 0) << threads << " threads";
  }
}

TEST(ForEachIndex, AFailingTaskStopsTheLoopAndIsRethrown) {
  for (const int threads : {1, 2, 4}) {
    std::atomic<int> ran{0};
    int reported = 0;
    EXPECT_THROW(ForEachIndex(
                     100, OnThreads(threads),
                     [&](int k) {
                       ++ran;
                       if (k == 3) throw std::runtime_error("task 3");
                       std::this_thread::sleep_for(std::chrono::milliseconds(1));
                     },
                     [&](int k) {
                       EXPECT_LT(k, 3);  // nothing at or after the failure is reported
                       ++reported;
                     }),
                 std::runtime_error);
    EXPECT_LT(ran.load(), 100) << threads << " threads";
    EXPECT_LE(reported, 3) << threads << " threads";
  }
}

TEST(ForEachIndex, AnErrorOfTheCallerIsPassedOnAndStopsTheRun) {
  for (const int threads : {1, 2}) {
    for (const bool as_finished : {false, true}) {
      Schedule schedule = OnThreads(threads);
      schedule.as_finished = as_finished;
      int reported = 0;
      EXPECT_THROW(ForEachIndex(
                       6, schedule, [](int) {},
                       [&](int) {
                         ++reported;
                         throw std::runtime_error("disk full");
                       }),
                   std::runtime_error);
      EXPECT_EQ(reported, 1) << threads << " threads, as finished " << as_finished;
    }
  }
}

TEST(ForEachIndex, NothingToDo) {
  for (const int threads : {1, 3}) {
    int calls = 0;
    ForEachIndex(
        0, OnThreads(threads), [&](int) { ++calls; }, [&](int) { ++calls; });
    EXPECT_EQ(calls, 0);
  }
}

}  // namespace
}  // namespace unjam::parallel
