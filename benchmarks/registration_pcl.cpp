// SPDX-License-Identifier: BSD-3-Clause
// bench_registration's PCL incumbent (see registration_incumbents.hpp and bench_registration.cpp).
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/transformation_estimation_point_to_plane_lls.h>

#include "registration_incumbents.hpp"

namespace nbs::bench {
namespace {

using Cloud = pcl::PointCloud<pcl::PointNormal>;

pcl::PointNormal point_normal(const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  pcl::PointNormal q;
  q.x = static_cast<float>(p.x()), q.y = static_cast<float>(p.y()), q.z = static_cast<float>(p.z());
  q.normal_x = static_cast<float>(n.x()), q.normal_y = static_cast<float>(n.y()), q.normal_z = static_cast<float>(n.z());
  return q;
}

class PclIcp final : public RegistrationIncumbent {
public:
  [[nodiscard]] std::string name() const override { return "pcl"; }
  void set_model(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals) override {
    target_.reset(new Cloud);
    target_->reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) target_->push_back(point_normal(points[i], normals[i]));
  }
  void set_source(const std::vector<Eigen::Vector3d>& points) override {
    source_.reset(new Cloud);  // the source's normals are not used by the point-to-plane estimation
    source_->reserve(points.size());
    for (const Eigen::Vector3d& p : points) source_->push_back(point_normal(p, Eigen::Vector3d::Zero()));
  }
  /// A new registration object per call: align() builds the target's kd-tree (setInputTarget marks it updated).
  /// PCL's default criteria stop at `iterations` (transformation epsilon 0, no fitness epsilon); no rejectors.
  [[nodiscard]] Eigen::Matrix4d align(double radius_m, int iterations) override {
    pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> icp;
    icp.setTransformationEstimation(
        pcl::make_shared<pcl::registration::TransformationEstimationPointToPlaneLLS<pcl::PointNormal, pcl::PointNormal>>());
    icp.setInputSource(source_);
    icp.setInputTarget(target_);
    icp.setMaxCorrespondenceDistance(radius_m);
    icp.setMaximumIterations(iterations);
    Cloud aligned;
    icp.align(aligned);
    return icp.getFinalTransformation().cast<double>();
  }

private:
  Cloud::Ptr target_, source_;
};

}  // namespace

std::unique_ptr<RegistrationIncumbent> make_pcl_icp() { return std::make_unique<PclIcp>(); }

}  // namespace nbs::bench
