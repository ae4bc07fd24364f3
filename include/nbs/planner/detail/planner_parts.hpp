// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Construction helpers of NbsPlanner: the voxel space (a NoiseModelSpace with the sensor's σ(d)), the termination
/// criterion and the collision checker from Parameters; the unknown-area check.

#include <algorithm>
#include <concepts>
#include <memory>
#include <type_traits>
#include <utility>

#include "nbs/planner/detail/components.hpp"
#include "nbs/space/block_flush.hpp"

namespace nbs::detail {

/// The voxel space of the planner: l_v = params.voxel_size_m over the bounding box of the unknown area. A
/// NoiseModelSpace gets σ(d) of the sensor's noise (clamped to ≥ 10 µm, the thesis model needs σ > 0); any other
/// space is built as Space(l_v, box). Throws InvalidArgument if l_v is not smaller than the box's smallest extent.
template <VoxelSpace Space, class Sensor>
[[nodiscard]] std::unique_ptr<Space> make_planner_space(const Parameters& params, const Aabb& box,
                                                        const Sensor& sensor) {
  const double extent = box.extent().minCoeff();  // box: checked by require_unknown_area
  detail::require(params.voxel_size_m < extent, "voxel_size_m = ", params.voxel_size_m,
                  " m must be smaller than the smallest extent of the unknown area's box, ", extent, " m");
  if constexpr (NoiseModelSpace<Space> && requires { sensor.noise.sigma_m(1.0); }) {
    typename Space::ModelType::Setting st;
    const auto noise = sensor.noise;
    st.sigma_m = [noise](double d) { return std::max(noise.sigma_m(d), 1e-5); };
    return std::make_unique<Space>(params.voxel_size_m, box, typename Space::ModelType(st));
  } else {
    return std::make_unique<Space>(params.voxel_size_m, box);
  }
}

/// Applies PlannerSetting::flush to the space's backend (nothing when it is off). Throws InvalidArgument if it is on
/// and the backend is not a FlushableBackend reachable through `space.mutable_backend()`.
/// A space whose backend, reached by `mutable_backend()`, is a FlushableBackend (a conjunction, so a space without
/// `mutable_backend()` is simply not one).
template <class Space>
concept FlushableSpace = requires(Space& s) { s.mutable_backend(); } &&
                         FlushableBackend<std::remove_cvref_t<decltype(std::declval<Space&>().mutable_backend())>>;

template <class Space>
void apply_flush_setting(Space& space, const BlockFlushSetting& flush) {
  if (!flush.enabled()) return;
  if constexpr (FlushableSpace<Space>) {
    space.mutable_backend().set_flush_policy(flush);
  } else {
    throw InvalidArgument(
        "PlannerSetting.flush: the planner's voxel space cannot flush blocks to disk (its backend is not a "
        "FlushableBackend, e.g. HashedBlockBackend)");
  }
}

/// The termination criterion from Parameters: SettledTermination / ThesisTermination by settled_termination /
/// thesis_termination(params), else Termination(params) if that exists, else Termination{}.
template <class Termination>
[[nodiscard]] Termination make_termination(const Parameters& params) {
  if constexpr (std::same_as<Termination, SettledTermination>) {
    return settled_termination(params);
  } else if constexpr (std::same_as<Termination, ThesisTermination>) {
    return thesis_termination(params);
  } else if constexpr (std::constructible_from<Termination, const Parameters&>) {
    return Termination(params);
  } else {
    return Termination{};
  }
}

/// The collision checker: Collision{} if default-constructible, else Collision(space, Collision::Setting{})
/// (e.g. VoxelCollisionChecker, which borrows the planner's space; the space lives on the heap, so it stays put).
template <class Collision, class Space>
[[nodiscard]] Collision make_collision(const Space& space) {
  if constexpr (std::default_initializable<Collision>) {
    return Collision{};
  } else {
    static_assert(std::constructible_from<Collision, const Space&, typename Collision::Setting>,
                  "NbsPlanner: the collision checker must be default-constructible or constructible from "
                  "(const Space&, Collision::Setting)");
    return Collision(space, typename Collision::Setting{});
  }
}

/// Throws InvalidArgument unless `box` is a finite, non-empty box with positive extent on every axis.
inline void require_unknown_area(const Aabb& box) {
  require(!box.empty() && box.min.allFinite() && box.max.allFinite(),
          "bounding box of the unknown area must be finite and non-empty, got min (", box.min.transpose(), ") max (",
          box.max.transpose(), ")");
  require((box.extent().array() > 0.0).all(), "bounding box of the unknown area must have extent > 0 on every axis, ",
          "got (", box.extent().transpose(), ")");
}

}  // namespace nbs::detail
