// SPDX-License-Identifier: BSD-3-Clause
// bench_recognition's PCL incumbent (see recognition_incumbents.hpp and bench_recognition.cpp).
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/features/ppf.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/ppf_registration.h>

#include "recognition_incumbents.hpp"

namespace nbs::bench {
namespace {

using Cloud = pcl::PointCloud<pcl::PointNormal>;

Cloud::Ptr cloud(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals) {
  Cloud::Ptr c(new Cloud);
  c->reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    pcl::PointNormal q;
    q.getVector3fMap() = points[i].cast<float>();
    q.getNormalVector3fMap() = normals[i].cast<float>();
    c->push_back(q);
  }
  return c;
}

class PclPpf final : public RecognitionIncumbent {
public:
  [[nodiscard]] std::string name() const override { return "pcl"; }
  /// All ordered pairs of the model (PPFEstimation) into the hash map, PCL's model description.
  void set_model(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                 const PpfParameters& p) override {
    pcl::console::setVerbosityLevel(pcl::console::L_ERROR);  // align() prints the accumulator size at L_INFO
    p_ = p;
    model_ = cloud(points, normals);
    pcl::PPFEstimation<pcl::PointNormal, pcl::PointNormal, pcl::PPFSignature> est;
    est.setInputCloud(model_);
    est.setInputNormals(model_);
    pcl::PointCloud<pcl::PPFSignature>::Ptr features(new pcl::PointCloud<pcl::PPFSignature>);
    est.compute(*features);
    hash_.reset(new pcl::PPFHashMapSearch(static_cast<float>(p.angle_step_rad), static_cast<float>(p.distance_step_m)));
    hash_->setInputFeatureCloud(features);
  }
  void set_scene(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals) override {
    scene_ = cloud(points, normals);
  }
  /// A new registration object per call: setInputTarget builds the scene's kd-tree.
  [[nodiscard]] Eigen::Matrix4d match() override {
    pcl::PPFRegistration<pcl::PointNormal, pcl::PointNormal> reg;
    reg.setSceneReferencePointSamplingRate(p_.reference_step);
    reg.setPositionClusteringThreshold(static_cast<float>(p_.cluster_translation_m));
    reg.setRotationClusteringThreshold(static_cast<float>(p_.cluster_rotation_rad));
    reg.setSearchMethod(hash_);
    reg.setInputSource(model_);
    reg.setInputTarget(scene_);
    Cloud aligned;
    reg.align(aligned);
    return reg.getFinalTransformation().cast<double>();
  }

private:
  PpfParameters p_;
  Cloud::Ptr model_, scene_;
  pcl::PPFHashMapSearch::Ptr hash_;
};

}  // namespace

std::unique_ptr<RecognitionIncumbent> make_pcl_ppf() { return std::make_unique<PclPpf>(); }

}  // namespace nbs::bench
