// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The incumbents of bench_registration (Open3D, PCL), each in a translation unit of its own so that their headers
/// and compile options stay out of the nbs code (benchmarks/registration.cmake adds the units that are found).
/// `set_model` and `set_source` convert into the incumbent's data layout (not timed); `align` is the timed call:
/// point-to-plane ICP of the source to the model from the identity, correspondence distance `radius_m`, exactly
/// `iterations` iterations, building the model's search tree inside the call. Returns the correction (source → model).

#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

namespace nbs::bench {

class RegistrationIncumbent {
public:
  virtual ~RegistrationIncumbent() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  virtual void set_model(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals) = 0;
  virtual void set_source(const std::vector<Eigen::Vector3d>& points) = 0;
  [[nodiscard]] virtual Eigen::Matrix4d align(double radius_m, int iterations) = 0;
};

/// Open3D 0.16 RegistrationICP with TransformationEstimationPointToPlane, OpenMP threads set to 1.
[[nodiscard]] std::unique_ptr<RegistrationIncumbent> make_open3d_icp();
/// PCL 1.13 IterativeClosestPointWithNormals with TransformationEstimationPointToPlaneLLS.
[[nodiscard]] std::unique_ptr<RegistrationIncumbent> make_pcl_icp();

}  // namespace nbs::bench
