// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer target: NbsPlanner::integrate on a scan decoded from the input. A scan the planner rejects
// (InvalidArgument) must leave it unchanged (n_s, the space's totals, the mesh's counters); a scan it takes must
// leave the mesh consistent (check_invariants). Anything else — another exception, a crash, a sanitizer report — is
// a finding. The planner is small (6 cm box at 1 cm voxels, 20-ray profiles) so that one input costs little.
//
// Input layout (bytes past the end read as 0):
//   [0]          profiles − 1 (mod 4) and flags: bit 2 = raw-float coordinates, bit 3 = raw 3×4 pose matrices
//   per profile  a pose: 4 × int16 quaternion + 3 × int16 translation (±0.3 m), or 12 raw floats
//   then         points of 7 bytes: 3 × int16 (±0.12 m; 32767 = NaN, −32768 = 1e30) or 3 raw floats, and a profile
//                index byte (mod profiles + 1, so that one value is out of range); at most 128 points (the mesh stage costs ~70 µs per point under ASan)
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>

#include "nbs/mesh/invariants.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/sensor/presets.hpp"

namespace {

struct Reader {
  const std::uint8_t* data;
  std::size_t size, at = 0;
  [[nodiscard]] bool done() const { return at >= size; }
  std::uint8_t byte() { return at < size ? data[at++] : 0; }
  std::int16_t i16() { return static_cast<std::int16_t>(static_cast<std::uint16_t>(byte() | (byte() << 8))); }
  float f32() {
    std::uint32_t u = 0;
    for (int k = 0; k < 4; ++k) u |= static_cast<std::uint32_t>(byte()) << (8 * k);
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
  }
  double coordinate(bool raw, double scale) {
    if (raw) return f32();
    const std::int16_t v = i16();
    if (v == std::numeric_limits<std::int16_t>::max()) return std::numeric_limits<double>::quiet_NaN();
    if (v == std::numeric_limits<std::int16_t>::min()) return 1e30;
    return scale * v / 32767.0;
  }
};

nbs::Scan decode(Reader& in) {
  const std::uint8_t head = in.byte();
  const unsigned profiles = 1 + (head & 3u);
  const bool raw_coords = (head & 4u) != 0, raw_poses = (head & 8u) != 0;
  nbs::Scan scan;
  for (unsigned k = 0; k < profiles; ++k) {
    nbs::Pose pose = nbs::Pose::Identity();
    if (raw_poses) {
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = in.f32();
    } else {
      Eigen::Quaterniond q(in.i16(), in.i16(), in.i16(), in.i16());
      if (q.norm() > 0.0) q.normalize();
      pose.linear() = q.toRotationMatrix();
      pose.translation() = nbs::Vec3(in.coordinate(false, 0.3), in.coordinate(false, 0.3), in.coordinate(false, 0.3));
    }
    scan.profile_poses.push_back(pose);
  }
  while (!in.done() && scan.points.size() < 128) {
    const double x = in.coordinate(raw_coords, 0.12), y = in.coordinate(raw_coords, 0.12),
                 z = in.coordinate(raw_coords, 0.12);
    scan.add_point(nbs::Vec3(x, y, z), in.byte() % (profiles + 1));
  }
  return scan;
}

nbs::Parameters small_parameters() {
  nbs::Parameters p;
  p.voxel_size_m = 0.01;
  return p;
}

nbs::LaserStripeProfiler small_sensor() {
  nbs::LaserStripeProfiler s = nbs::presets::dlr_lsp();
  s.points_per_profile = 20;
  return s;
}

struct State {
  int scans;
  std::size_t vertices, faces;
  nbs::IntegrationStats totals;
  bool operator==(const State& o) const {
    return scans == o.scans && vertices == o.vertices && faces == o.faces &&
           totals.points == o.totals.points && totals.integrated == o.totals.integrated &&
           totals.voxel_updates == o.totals.voxel_updates;
  }
};

template <class P>
State state_of(const P& p) {
  return {p.scans(), p.mesh().vertex_count(), p.mesh().face_count(), p.space().totals()};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const nbs::Parameters params = small_parameters();
  static const nbs::LaserStripeProfiler sensor = small_sensor();
  static const nbs::Aabb box{nbs::Vec3(-0.03, -0.03, 0.0), nbs::Vec3(0.03, 0.03, 0.06)};
  // Every input meets a fresh planner: one that only rejected scans is still fresh (checked below), so it is
  // kept; one that took a scan is replaced before the next input.
  static std::optional<nbs::NbsPlanner<>> planner;
  if (!planner) planner.emplace(params, sensor, box);
  Reader in{data, size};
  const nbs::Scan scan = decode(in);
  const State before = state_of(*planner);
  try {
    (void)planner->integrate(scan);
  } catch (const nbs::InvalidArgument&) {
    if (!(state_of(*planner) == before)) std::abort();  // a rejected scan changed the planner
    return 0;
  }
  const bool consistent = nbs::check_invariants(planner->mesh(), params.reduction_radius_m).ok();
  planner.reset();
  if (!consistent) std::abort();
  return 0;
}
