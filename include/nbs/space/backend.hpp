// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The VoxelBackend concept: storage of one state per voxel, adapted through `backend_traits<B>`.
///
/// A backend stores a `State` per *observed* voxel; a voxel never written reads as `State{}` (unknown). The default
/// traits forward to member functions of B; specialise `backend_traits` to adapt a foreign map without touching it
/// (the OctoMap adapter does so for `octomap::OcTree`). Use the free functions below, never the traits directly.
///
/// Thread-safety: concurrent const calls are safe for every backend nbs ships; writes need exclusive access.

#include <concepts>
#include <cstddef>
#include <type_traits>

#include "nbs/space/voxel_key.hpp"

namespace nbs {

/// Customisation point. The primary template forwards to members of B:
/// `State`, `B(double resolution_m)`, `resolution_m()`, `get(key)`, `observed(key)`, `set(key, state)`,
/// `for_each(f)` with f(const VoxelKey&, const State&), `size()`, `memory_bytes()`, `observed_key_bounds()`,
/// `key_range()` (the keys the backend can store).
template <class B>
struct backend_traits {
  using State = typename B::State;
  [[nodiscard]] static B make(double resolution_m) { return B(resolution_m); }
  [[nodiscard]] static double resolution_m(const B& b) { return b.resolution_m(); }
  [[nodiscard]] static State get(const B& b, const VoxelKey& k) { return b.get(k); }
  [[nodiscard]] static bool observed(const B& b, const VoxelKey& k) { return b.observed(k); }
  static void set(B& b, const VoxelKey& k, const State& s) { b.set(k, s); }
  template <class F>
  static void for_each(const B& b, F&& f) {
    b.for_each(static_cast<F&&>(f));
  }
  [[nodiscard]] static std::size_t size(const B& b) { return b.size(); }
  [[nodiscard]] static std::size_t memory_bytes(const B& b) { return b.memory_bytes(); }
  [[nodiscard]] static KeyBox observed_key_bounds(const B& b) { return b.observed_key_bounds(); }
  [[nodiscard]] static KeyBox key_range(const B& b) { return b.key_range(); }
};

/// State type stored by backend B.
template <class B>
using backend_state_t = typename backend_traits<B>::State;

namespace detail {
template <class S>
struct StateSink {
  void operator()(const VoxelKey&, const S&) const {}
};
}  // namespace detail

/// A voxel storage usable by ProbabilisticVoxelSpace. Checked where the space is instantiated, so a type that
/// misses an operation fails there with the missing expression listed.
template <class B>
concept VoxelBackend = std::default_initializable<backend_state_t<B>> && std::copyable<backend_state_t<B>> &&
    requires(B& b, const B& cb, const VoxelKey& k, const backend_state_t<B>& s, double resolution_m) {
      { backend_traits<B>::make(resolution_m) } -> std::same_as<B>;
      { backend_traits<B>::resolution_m(cb) } -> std::convertible_to<double>;
      { backend_traits<B>::get(cb, k) } -> std::convertible_to<backend_state_t<B>>;
      { backend_traits<B>::observed(cb, k) } -> std::convertible_to<bool>;
      backend_traits<B>::set(b, k, s);
      backend_traits<B>::for_each(cb, detail::StateSink<backend_state_t<B>>{});
      { backend_traits<B>::size(cb) } -> std::convertible_to<std::size_t>;
      { backend_traits<B>::memory_bytes(cb) } -> std::convertible_to<std::size_t>;
      { backend_traits<B>::observed_key_bounds(cb) } -> std::same_as<KeyBox>;
      { backend_traits<B>::key_range(cb) } -> std::same_as<KeyBox>;
    };

// ---- Free functions (the API users and nbs call) --------------------------------------------------------------------

/// Edge length l_v in metres.
template <VoxelBackend B>
[[nodiscard]] double resolution_m(const B& b) { return backend_traits<B>::resolution_m(b); }
/// State of voxel k; `State{}` (unknown) if never written.
template <VoxelBackend B>
[[nodiscard]] backend_state_t<B> voxel_state(const B& b, const VoxelKey& k) { return backend_traits<B>::get(b, k); }
/// True if voxel k has been written.
template <VoxelBackend B>
[[nodiscard]] bool is_observed(const B& b, const VoxelKey& k) { return backend_traits<B>::observed(b, k); }
/// Writes the state of voxel k (marks it observed).
template <VoxelBackend B>
void set_voxel_state(B& b, const VoxelKey& k, const backend_state_t<B>& s) { backend_traits<B>::set(b, k, s); }
/// Calls f(key, state) once per observed voxel, in unspecified order.
template <VoxelBackend B, class F>
void for_each_voxel(const B& b, F&& f) { backend_traits<B>::for_each(b, static_cast<F&&>(f)); }
/// Number of observed voxels.
template <VoxelBackend B>
[[nodiscard]] std::size_t observed_count(const B& b) { return backend_traits<B>::size(b); }
/// Heap bytes held by the backend (estimate, includes container overhead).
template <VoxelBackend B>
[[nodiscard]] std::size_t memory_bytes(const B& b) { return backend_traits<B>::memory_bytes(b); }
/// Smallest key box containing every observed voxel (empty if none).
template <VoxelBackend B>
[[nodiscard]] KeyBox observed_key_bounds(const B& b) { return backend_traits<B>::observed_key_bounds(b); }

}  // namespace nbs

namespace nbs {
/// Keys the backend can store; writing outside throws InvalidArgument.
template <VoxelBackend B>
[[nodiscard]] KeyBox key_range(const B& b) { return backend_traits<B>::key_range(b); }
}  // namespace nbs
