// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Minimal deterministic parallel loop over an index range with std::thread (no OpenMP).

#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace nbs::detail {

/// Number of worker threads for `requested` (0 = std::thread::hardware_concurrency(), at least 1).
[[nodiscard]] inline unsigned resolve_threads(unsigned requested) {
  if (requested > 0) return requested;
  return std::max(1u, std::thread::hardware_concurrency());
}

/// Calls `body(begin, end)` on disjoint contiguous blocks covering [0, n), on up to `threads` threads
/// (0 = hardware concurrency). Results are independent of the thread count as long as `body` writes only to
/// per-index outputs. The first exception thrown by any block is rethrown after all threads joined.
template <class Body>
void parallel_for(std::size_t n, unsigned threads, Body&& body) {
  if (n == 0) return;
  const std::size_t t = std::min<std::size_t>(resolve_threads(threads), n);
  if (t == 1) {
    body(std::size_t{0}, n);
    return;
  }
  std::vector<std::exception_ptr> errors(t);
  std::vector<std::thread> pool;
  pool.reserve(t);
  for (std::size_t k = 0; k < t; ++k) {
    const std::size_t begin = n * k / t;
    const std::size_t end = n * (k + 1) / t;
    pool.emplace_back([&, begin, end, k] {
      try {
        body(begin, end);
      } catch (...) {
        errors[k] = std::current_exception();
      }
    });
  }
  for (auto& th : pool) th.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace nbs::detail
