// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The UtilityTerm concept: a utility accumulated per simulated ray and per visited voxel, so that one ray cast
/// feeds several terms (Sec. 4.5.3), and `TermSet`, several terms fed by a single cast.
///
/// Call protocol for one candidate (the evaluator follows it; so must any other driver):
///   begin_candidate(i); for each ray { begin_ray(); visit(v) for each voxel in order; end_ray(e); } value();
/// A term object is used by one thread at a time; the evaluator gives every thread its own copy.

#include <array>
#include <concepts>
#include <cstddef>
#include <tuple>
#include <utility>

#include "nbs/utility/voxel_visit.hpp"

namespace nbs {

/// A utility term. `value()` is the candidate's utility after the last ray (higher = better).
/// Optional: `static constexpr bool kNeedsRays = false;` lets the evaluator skip the ray casts (e.g. Random).
template <class T>
concept UtilityTerm = std::copy_constructible<T> &&
    requires(T& t, const T& ct, std::size_t candidate, const VoxelVisit& v, const RayEnd& e) {
      t.begin_candidate(candidate);
      t.begin_ray();
      t.visit(v);
      t.end_ray(e);
      { ct.value() } -> std::convertible_to<double>;
    };

/// True unless T declares `kNeedsRays = false`.
template <class T>
[[nodiscard]] constexpr bool term_needs_rays() {
  if constexpr (requires { T::kNeedsRays; }) {
    return static_cast<bool>(T::kNeedsRays);
  } else {
    return true;
  }
}

/// True if `t.visit(v)` changes nothing unless `v.first_visit` — the term says so with an optional const member
/// `bool first_visits_only() const`. The evaluator then calls visit() only for first visits (fields unchanged,
/// `index` still counts every voxel of the ray); begin_ray/end_ray are called as always.
template <class T>
[[nodiscard]] bool visits_first_only(const T& t) {
  if constexpr (requires { { t.first_visits_only() } -> std::convertible_to<bool>; }) {
    return static_cast<bool>(t.first_visits_only());
  } else {
    return false;
  }
}

/// Several terms fed by one ray cast. `value()` is the value of the first term; read the others with `get<I>()`.
/// Models UtilityTerm itself, so sets nest.
template <UtilityTerm... Terms>
  requires(sizeof...(Terms) >= 1)
class TermSet {
public:
  static constexpr bool kNeedsRays = (term_needs_rays<Terms>() || ...);

  TermSet() = default;
  explicit TermSet(Terms... terms) : terms_(std::move(terms)...) {}

  void begin_candidate(std::size_t candidate) {
    std::apply([&](auto&... t) { (t.begin_candidate(candidate), ...); }, terms_);
  }
  void begin_ray() {
    std::apply([](auto&... t) { (t.begin_ray(), ...); }, terms_);
  }
  void visit(const VoxelVisit& v) {
    std::apply([&](auto&... t) { (t.visit(v), ...); }, terms_);
  }
  void end_ray(const RayEnd& e) {
    std::apply([&](auto&... t) { (t.end_ray(e), ...); }, terms_);
  }
  [[nodiscard]] double value() const { return static_cast<double>(std::get<0>(terms_).value()); }
  /// True if every term ignores repeated visits (see visits_first_only).
  [[nodiscard]] bool first_visits_only() const {
    return std::apply([](const auto&... t) { return (visits_first_only(t) && ...); }, terms_);
  }

  template <std::size_t I>
  [[nodiscard]] const auto& get() const {
    return std::get<I>(terms_);
  }
  template <std::size_t I>
  [[nodiscard]] auto& get() {
    return std::get<I>(terms_);
  }
  /// Values of all terms, in order.
  [[nodiscard]] auto values() const {
    return std::apply([](const auto&... t) { return std::array<double, sizeof...(Terms)>{double(t.value())...}; },
                      terms_);
  }

private:
  std::tuple<Terms...> terms_;
};

}  // namespace nbs
