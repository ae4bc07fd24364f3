// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Counter-based standard-normal numbers: the value for (seed, stream, index) does not depend on call order or
/// thread count, which makes simulated scans reproducible.

#include <cmath>
#include <cstdint>
#include <numbers>

namespace nbs {

/// SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mix.
[[nodiscard]] constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// N(0, 1) samples addressed by (stream, index), e.g. (profile, ray); seeded. Stateless and thread-safe.
class CounterGaussian {
public:
  explicit CounterGaussian(std::uint64_t seed) : key_(splitmix64(seed)) {}

  /// Standard-normal value number `index` of stream `stream` (Box–Muller on two hashed uniforms).
  [[nodiscard]] double operator()(std::uint64_t stream, std::uint64_t index) const {
    const std::uint64_t base = splitmix64(key_ ^ splitmix64(stream));
    const std::uint64_t h1 = splitmix64(base + 2 * index);
    const std::uint64_t h2 = splitmix64(base + 2 * index + 1);
    constexpr double k2pow53 = 1.0 / 9007199254740992.0;
    const double u1 = static_cast<double>((h1 >> 11) + 1) * k2pow53;  // (0, 1]
    const double u2 = static_cast<double>(h2 >> 11) * k2pow53;        // [0, 1)
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

private:
  std::uint64_t key_;
};

}  // namespace nbs
