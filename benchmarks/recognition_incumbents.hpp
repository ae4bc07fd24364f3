// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// bench_recognition's incumbent (PCL), in a translation unit of its own so that its headers and compile options
/// stay out of the nbs code (benchmarks/recognition.cmake adds the unit when PCL is found).
/// `set_model` builds the model description (timed by the caller as the build time); `set_scene` converts the
/// cluster into the incumbent's layout (not timed); `match` is the timed call: builds the scene's search tree and
/// returns the top pose hypothesis T_SM (model → scene frame).

#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

namespace nbs::bench {

/// The parameters both sides share (nbs's PpfModelSetting / PpfMatchSetting defaults, resolved for the model).
struct PpfParameters {
  double distance_step_m = 0.0;   ///< d_dist = τ_d · model diameter, metres.
  double angle_step_rad = 0.0;    ///< d_angle, radians.
  unsigned reference_step = 5;    ///< every n-th scene point is a reference point.
  double cluster_translation_m = 0.0;  ///< pose clustering: translation cut-off, metres.
  double cluster_rotation_rad = 0.0;   ///< pose clustering: rotation cut-off, radians.
};

class RecognitionIncumbent {
public:
  virtual ~RecognitionIncumbent() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  virtual void set_model(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                         const PpfParameters& p) = 0;
  virtual void set_scene(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals) = 0;
  [[nodiscard]] virtual Eigen::Matrix4d match() = 0;
};

/// PCL 1.13: PPFEstimation + PPFHashMapSearch for the model, PPFRegistration for the scene.
[[nodiscard]] std::unique_ptr<RecognitionIncumbent> make_pcl_ppf();

}  // namespace nbs::bench
