// SPDX-License-Identifier: BSD-3-Clause
// bench_registration's Open3D incumbent (see registration_incumbents.hpp and bench_registration.cpp).
#include <omp.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/pipelines/registration/TransformationEstimation.h>

#include "registration_incumbents.hpp"

namespace nbs::bench {
namespace {

namespace o3r = open3d::pipelines::registration;

class Open3dIcp final : public RegistrationIncumbent {
public:
  Open3dIcp() { omp_set_num_threads(1); }  // nbs::Icp is single-threaded; Open3D's ICP loops are OpenMP loops
  [[nodiscard]] std::string name() const override { return "open3d"; }
  void set_model(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals) override {
    target_.points_ = points;
    target_.normals_ = normals;
  }
  void set_source(const std::vector<Eigen::Vector3d>& points) override { source_.points_ = points; }
  /// RegistrationICP builds its KDTreeFlann over the target and copies the source inside the call; it runs
  /// `iterations` updates and iterations + 1 correspondence searches (the last scores the result). Relative fitness
  /// and RMSE 0: never stops early.
  [[nodiscard]] Eigen::Matrix4d align(double radius_m, int iterations) override {
    const o3r::RegistrationResult r =
        o3r::RegistrationICP(source_, target_, radius_m, Eigen::Matrix4d::Identity(),
                             o3r::TransformationEstimationPointToPlane(), o3r::ICPConvergenceCriteria(0.0, 0.0, iterations));
    return r.transformation_;
  }

private:
  open3d::geometry::PointCloud target_, source_;
};

}  // namespace

std::unique_ptr<RegistrationIncumbent> make_open3d_icp() { return std::make_unique<Open3dIcp>(); }

}  // namespace nbs::bench
