// SPDX-License-Identifier: BSD-3-Clause
// The RegistrationPolicy conformance suite (tests/conformance/registration_conformance.hpp) on every policy in the
// repo and on a minimal user policy, over analytic cases: a structured surface with a pose error (Icp applies), a
// plane (Icp refuses as degenerate), an empty model, an empty scan.

#include "nbs_catch.hpp"

#include <numbers>

#include "conformance/registration_conformance.hpp"
#include "nbs/registration/icp.hpp"
#include "nbs/registration/selectable_registration.hpp"
#include "support/synthetic.hpp"

namespace {

using nbs::Pose;
using nbs::RegistrationResult;
using nbs::RegistrationStatus;
using nbs::Scan;
using nbs::Vec3;
using namespace nbs::test;

/// A minimal user policy: translates the scan's centroid onto the centroid of the model's vertices with a normal.
struct CentroidShift {
  template <nbs::NormalMesh Mesh>
  [[nodiscard]] RegistrationResult register_scan(const Scan& scan, const Mesh& mesh) const {
    RegistrationResult r;
    Vec3 model = Vec3::Zero();
    std::size_t n = 0;
    for (nbs::VertexId v = 0; v < mesh.vertex_count(); ++v)
      if (mesh.has_normal(v)) model += mesh.position(v), ++n;
    if (n == 0 || scan.empty()) {
      r.status = n == 0 ? RegistrationStatus::refused_empty_model : RegistrationStatus::refused_few_points;
      r.reason = "nothing to align";
      return r;
    }
    r.status = RegistrationStatus::applied;
    r.correction.translation() = model / static_cast<double>(n) - centroid(scan);
    r.scan_points = scan.size();
    return r;
  }
};
static_assert(nbs::RegistrationPolicy<CentroidShift, PointModel>);
static_assert(nbs::RegistrationPolicy<nbs::Icp, PointModel>);
static_assert(nbs::RegistrationPolicy<nbs::NoRegistration, PointModel>);
static_assert(nbs::RegistrationPolicy<nbs::SelectableRegistration, PointModel>);

struct ConformanceCase {
  const char* name;
  Scan scan;
  PointModel model;
};

std::vector<ConformanceCase> cases() {
  const PointModel bumps = model_of(bumpy_plane()), plane = model_of(flat_plane());
  const Scan scan = scan_of(bumpy_plane(), Vec3(0.02, -0.05, 0.25), Vec3::Zero(), 2e-5, 3);
  const Pose error = pose_error(Vec3(0.001, 0.0005, -0.0008), 0.002, Vec3(1.0, 0.2, 0.4), centroid(scan));
  const Scan plane_scan = scan_of(flat_plane(), Vec3(0.02, -0.05, 0.25), Vec3::Zero(), 2e-5, 3);
  return {{"bumpy plane with a pose error", nbs::transformed(scan, error), bumps},
          {"plane", nbs::transformed(plane_scan, error), plane},
          {"empty model", scan, PointModel{}},
          {"empty scan", Scan{}, bumps}};
}

template <class Policy>
std::vector<RegistrationResult> run_all(Policy policy) {
  std::vector<RegistrationResult> out;
  for (const ConformanceCase& c : cases()) {
    INFO(c.name);
    out.push_back(nbs::conformance::check_registration_conformance(policy, c.scan, c.model));
  }
  return out;
}

}  // namespace

TEST_CASE("registration conformance: NoRegistration never changes a scan", "[registration][conformance]") {
  for (const RegistrationResult& r : run_all(nbs::NoRegistration{})) CHECK(r.status == RegistrationStatus::not_run);
  for (const RegistrationResult& r : run_all(nbs::SelectableRegistration{}))
    CHECK(r.status == RegistrationStatus::not_run);
}

TEST_CASE("registration conformance: Icp, directly and through SelectableRegistration", "[registration][conformance]") {
  const std::vector<RegistrationResult> direct = run_all(nbs::Icp{});
  const std::vector<RegistrationResult> selected =
      run_all(nbs::SelectableRegistration{nbs::RegistrationMethod::icp, nbs::IcpSetting{}});
  REQUIRE(direct.size() == 4);
  CHECK(direct[0].status == RegistrationStatus::applied);
  CHECK(direct[1].status == RegistrationStatus::refused_degenerate);
  CHECK(direct[2].status == RegistrationStatus::refused_empty_model);
  CHECK(direct[3].status == RegistrationStatus::refused_few_points);
  for (std::size_t i = 0; i < direct.size(); ++i) nbs::conformance::check_same_result(direct[i], selected[i]);
}

TEST_CASE("registration conformance: a user policy", "[registration][conformance]") {
  const std::vector<RegistrationResult> r = run_all(CentroidShift{});
  CHECK(r[0].status == RegistrationStatus::applied);
  CHECK(r[2].status == RegistrationStatus::refused_empty_model);
}

TEST_CASE("registration: method names parse and print", "[registration]") {
  CHECK(nbs::parse_registration_method("none") == nbs::RegistrationMethod::none);
  CHECK(nbs::parse_registration_method("icp") == nbs::RegistrationMethod::icp);
  CHECK(nbs::to_string(nbs::RegistrationMethod::icp) == "icp");
  CHECK_THROWS_AS(nbs::parse_registration_method("ICP"), nbs::InvalidArgument);
  CHECK(nbs::to_string(RegistrationStatus::refused_degenerate) == "refused_degenerate");
}
