// The wall-clock limit of one solve (SolverOptions::time_limit). A backend makes one when it
// starts and checks it between its iterations; a solve it calls inside (newton's NSGS
// warm-up, a convex step of the De Saxcé fixed point) gets what is left. A backend stopped
// by it returns its best iterate with status kIterationLimit and TimeLimitMessage.
// Internal to src/solvers.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace unjam::solvers_internal {

class Deadline {
 public:
  explicit Deadline(double seconds)
      : seconds_(seconds), limited_(std::isfinite(seconds)), start_(Clock::now()) {}
  bool Passed() const { return limited_ && Elapsed() >= seconds_; }
  // Seconds left (0 once passed); infinite without a limit.
  double SecondsLeft() const {
    if (!limited_) return std::numeric_limits<double>::infinity();
    return std::max(0.0, seconds_ - Elapsed());
  }

 private:
  using Clock = std::chrono::steady_clock;
  double Elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  double seconds_;
  bool limited_;
  Clock::time_point start_;
};

inline std::string TimeLimitMessage(double seconds) {
  char text[96];
  std::snprintf(text, sizeof text, "time limit of %g s reached before the tolerance", seconds);
  return text;
}

}  // namespace unjam::solvers_internal
