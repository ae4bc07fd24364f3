// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Local registration of a whole scan to the current model with the thesis's ICP variant (Sec. 3.2.3):
/// correspondences within a radius (3 mm), discarded when their normals differ by more than 60°, point-to-plane
/// error, a small fixed number of iterations (2–3: more iterations contract the model, Fig. 3.6).
/// SKELETON: the algorithm is being written on branch `icp`; this stub refuses every scan.

#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>

#include "nbs/registration/registration.hpp"

namespace nbs {

/// Settings of Icp. Throws InvalidArgument from validate() naming the bad field.
struct IcpSetting {
  double radius_m = 0.003;            ///< correspondence radius (thesis: 3 mm)
  double max_normal_angle_rad = 60.0 * std::numbers::pi / 180.0;  ///< normal compatibility (thesis: 60°)
  int iterations = 2;                 ///< fixed iteration count (thesis: 2–3); the upper bound with `converge`
  /// Convergence criterion (option): stop early when one iteration's update is below both bounds; then
  /// `iterations` is only the upper bound. Empty: always run `iterations` iterations (the thesis).
  struct Convergence {
    double translation_m = 1e-5;
    double rotation_rad = 1e-5;
    bool operator==(const Convergence&) const = default;
  };
  std::optional<Convergence> converge;
  double normal_radius_m = 0.0;       ///< radius of the scan's normal estimation; 0 = radius_m
  std::size_t min_correspondences = 100;  ///< refuse with fewer
  double min_condition = 1e-3;        ///< refuse when λ_min/λ_max of the scaled normal matrix is below
  double max_translation_m = 0.02;    ///< refuse a correction that moves the scan centroid farther
  double max_rotation_rad = 5.0 * std::numbers::pi / 180.0;  ///< refuse a larger correction rotation

  void validate() const;
  bool operator==(const IcpSetting&) const = default;
};

/// The thesis's ICP as a RegistrationPolicy over any NormalMesh.
class Icp {
public:
  IcpSetting setting{};

  Icp() = default;
  explicit Icp(const IcpSetting& s) : setting(s) {}

  template <NormalMesh Mesh>
  [[nodiscard]] RegistrationResult register_scan(const Scan&, const Mesh&) const {
    RegistrationResult r;
    r.status = RegistrationStatus::refused_few_points;
    r.reason = "ICP not implemented yet (skeleton)";
    return r;
  }
};

inline void IcpSetting::validate() const {}

}  // namespace nbs
