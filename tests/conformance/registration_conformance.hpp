// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance harness for nbs::RegistrationPolicy (include/nbs/registration/registration.hpp), run on any policy
// with any NormalMesh. Checked contract, for each (scan, mesh) case:
//  - the result is finite: correction rigid (validate_pose) and finite, rms/condition/t_s finite and ≥ 0;
//  - the correction is the identity unless status == applied; a refusal has a reason, `not_run` only for a policy
//    that never registers;
//  - the mesh is unchanged (vertex count, positions, normals, has_normal);
//  - deterministic: a second call, and a call on a copy of the policy, give bit-identical results (t_s aside).
// (Scans are valid: the planner validates them before it calls the policy.)
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include "nbs/registration/registration.hpp"

namespace nbs::conformance {

template <NormalMesh Mesh>
struct MeshSnapshot {
  std::vector<Vec3> positions, normals;
  std::vector<bool> with_normal;
  explicit MeshSnapshot(const Mesh& m) {
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
      const auto id = static_cast<VertexId>(v);
      positions.push_back(m.position(id));
      normals.push_back(m.normal(id));
      with_normal.push_back(m.has_normal(id));
    }
  }
  bool operator==(const MeshSnapshot&) const = default;
};

inline void check_same_result(const RegistrationResult& a, const RegistrationResult& b) {
  CHECK(a.status == b.status);
  CHECK(a.correction.matrix() == b.correction.matrix());
  CHECK(a.scan_points == b.scan_points);
  CHECK(a.correspondences == b.correspondences);
  CHECK(a.iterations == b.iterations);
  CHECK(a.rms_before_m == b.rms_before_m);
  CHECK(a.rms_after_m == b.rms_after_m);
  CHECK(a.condition == b.condition);
  CHECK(a.reason == b.reason);
}

/// Runs the contract above for `policy` on `scan` against `mesh`; returns the result for case-specific checks.
template <class Policy, NormalMesh Mesh>
  requires RegistrationPolicy<Policy, Mesh>
RegistrationResult check_registration_conformance(Policy& policy, const Scan& scan, const Mesh& mesh) {
  const MeshSnapshot<Mesh> before(mesh);
  const RegistrationResult r = policy.register_scan(scan, mesh);
  INFO("status " << to_string(r.status) << ": " << r.reason);
  CHECK(MeshSnapshot<Mesh>(mesh) == before);

  CHECK_NOTHROW(validate_pose(r.correction, "correction"));
  CHECK(r.correction.matrix().allFinite());
  for (double x : {r.rms_before_m, r.rms_after_m, r.condition, r.t_s}) {
    CHECK(std::isfinite(x));
    CHECK(x >= 0.0);
  }
  if (!r.applied()) CHECK(r.correction.matrix() == Pose::Identity().matrix());
  if (r.status != RegistrationStatus::applied && r.status != RegistrationStatus::not_run) CHECK_FALSE(r.reason.empty());

  check_same_result(r, policy.register_scan(scan, mesh));
  Policy copy = policy;
  check_same_result(r, copy.register_scan(scan, mesh));

  return r;
}

}  // namespace nbs::conformance
