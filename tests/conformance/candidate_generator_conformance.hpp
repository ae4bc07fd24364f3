// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Conformance harness for nbs::CandidateGenerator (include/nbs/candidates/candidate_generator.hpp). For each given
// context the checked contract is:
//  - generate(ctx) is const and deterministic: twice the same candidates (bit for bit);
//  - the status explains an empty list: status == ok iff there are candidates;
//  - every candidate is finite with a right-handed orthonormal rotation, moves along its s_y (zero length for an
//    area sensor, unless `area_paths_zero_length` is false), and its aim lies at d_s along s_z from the path line (ScanCandidate's invariant);
//  - an invalid context (d_s outside the working range, NaN d_s, non-rigid last pose, zero FOV) throws
//    InvalidArgument.
#include "nbs_catch.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include "nbs/candidates/candidate_generator.hpp"

namespace nbs::conformance {

namespace detail {
inline bool same_candidates(const CandidateSet& a, const CandidateSet& b) {
  if (a.status != b.status || a.candidates.size() != b.candidates.size()) return false;
  for (std::size_t i = 0; i < a.candidates.size(); ++i) {
    const ScanCandidate &x = a.candidates[i], &y = b.candidates[i];
    if (x.path.start().pose().matrix() != y.path.start().pose().matrix() ||
        x.path.end_position() != y.path.end_position() || x.aim.point != y.aim.point || x.source != y.source ||
        x.index != y.index || x.targets.size() != y.targets.size())
      return false;
  }
  return true;
}
}  // namespace detail

/// Returns the number of candidates over all contexts (so callers can require that some context gave some).
template <class G, class Mesh, class Space>
std::size_t check_candidate_generator_conformance(const G& gen, const std::vector<PlanningContext<Mesh, Space>>& ctxs,
                                                  bool area_paths_zero_length = true) {
  static_assert(CandidateGenerator<G, Mesh, Space>);
  std::size_t total = 0;
  for (std::size_t k = 0; k < ctxs.size(); ++k) {
    INFO("context " << k);
    const auto& ctx = ctxs[k];
    const CandidateSet set = gen.generate(ctx);
    CHECK(detail::same_candidates(set, gen.generate(ctx)));
    CHECK((set.status == CandidateStatus::ok) == !set.candidates.empty());
    const double d_s = ctx.standoff();
    for (const ScanCandidate& c : set.candidates) {
      const Pose& p = c.path.start().pose();
      REQUIRE(p.matrix().allFinite());
      REQUIRE(c.path.end_position().allFinite());
      REQUIRE(c.aim.point.allFinite());
      const Mat3 r = p.linear();
      CHECK((r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-9);
      CHECK(r.determinant() == Approx(1.0).margin(1e-9));
      const Vec3 move = c.path.end_position() - c.path.start().position();
      if (area_paths_zero_length && ctx.sensor.kind == SensorGeometry::Kind::area) CHECK(c.path.length() == 0.0);
      if (move.norm() > 0.0) CHECK(move.normalized().dot(r.col(1)) == Approx(1.0).margin(1e-9));
      const Vec3 rel = c.aim.point - p.translation();
      CHECK(rel.dot(r.col(2)) == Approx(d_s).margin(1e-9));
      CHECK((rel - d_s * r.col(2)).cross(r.col(1)).norm() < 1e-9);
    }
    total += set.candidates.size();

    auto far = ctx;
    far.standoff_m = ctx.sensor.range.max_m * 2.0;
    CHECK_THROWS_AS(gen.generate(far), InvalidArgument);
    auto nan = ctx;
    nan.standoff_m = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(gen.generate(nan), InvalidArgument);
    auto skew = ctx;
    skew.last_sensor.linear()(0, 0) = 2.0;
    CHECK_THROWS_AS(gen.generate(skew), InvalidArgument);
    auto blind = ctx;
    blind.sensor.fov_x_rad = 0.0;
    CHECK_THROWS_AS(gen.generate(blind), InvalidArgument);
  }
  return total;
}

}  // namespace nbs::conformance
