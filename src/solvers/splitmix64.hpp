// SplitMix64 (Steele, Lea & Flood 2014): a tiny, fast, well-mixed 64-bit generator, and its
// output function as a hash. Internal to src/solvers: NSGS's random sweep order
// (sweeps.hpp), and Lemke's basis keys and perturbation weights (lemke_mlcp.cpp, lemke.cpp).
#pragma once

#include <cstdint>

namespace unjam::solvers_internal {

// The generator's output for the state x: a well-mixed hash of x.
inline std::uint64_t SplitMix64Hash(std::uint64_t x) {
  std::uint64_t z = x + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t Next() {
    const std::uint64_t x = state;
    state += 0x9E3779B97F4A7C15ull;
    return SplitMix64Hash(x);
  }
  std::uint32_t Below(std::uint32_t n) {  // Lemire's multiply-shift, bias < 2⁻³²·n
    return static_cast<std::uint32_t>(((Next() >> 32) * n) >> 32);
  }
};

}  // namespace unjam::solvers_internal
