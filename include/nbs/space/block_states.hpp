// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// How a block of HashedBlockBackend lays out the states of its 8³ voxels: `BlockStates<State>`.
///
/// The primary template is a flat array of `State` (any trivially copyable state). Specialise it for a state that
/// has a more compact layout; thesis_model.hpp does so for ThesisState (split arrays and a surface side-car that is
/// allocated only for blocks with surface evidence). A specialisation provides, for voxel index i ∈ [0, 512):
/// `State load(int i) const`, `void store(int i, const State&)` (load(i) == s after store(i, s)), `heap_bytes()`
/// (bytes allocated beyond sizeof), and the serialisation `save(write)` / `restore(read)` used to flush a block to
/// disk, with write(const void*, std::size_t) and read(void*, std::size_t) (read returns false on a short read).

#include <array>
#include <cstddef>
#include <type_traits>

namespace nbs {

/// Voxels per block of HashedBlockBackend (8³).
inline constexpr int kBlockVoxels = 512;

/// Flat layout: one `State` per voxel, State{} = unknown.
template <class State>
struct BlockStates {
  static_assert(std::is_trivially_copyable_v<State>, "BlockStates: specialise it for a non-trivially-copyable state");
  std::array<State, kBlockVoxels> states{};

  [[nodiscard]] State load(int i) const { return states[i]; }
  void store(int i, const State& s) { states[i] = s; }
  [[nodiscard]] std::size_t heap_bytes() const { return 0; }
  template <class Write>
  void save(Write&& write) const {
    write(states.data(), sizeof(states));
  }
  template <class Read>
  [[nodiscard]] bool restore(Read&& read) {
    return read(states.data(), sizeof(states));
  }
};

}  // namespace nbs
