// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Portable seeded random numbers (simulation metrics, planner and utility seeds): std::mt19937_64 (its output
/// sequence is fixed by the standard) and our own conversions, so a seed gives the same samples with every standard
/// library.

#include <cstdint>
#include <random>

namespace nbs::detail {

/// Uniform double in [0, 1) from the top 53 bits of one engine draw.
[[nodiscard]] inline double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// SplitMix64 finaliser: a well-mixed 64-bit hash of `x` (used to derive choices from seeds).
[[nodiscard]] constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

}  // namespace nbs::detail
