// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Embree scene built from an IndexedMesh: a model of the nbs::RayCaster concept plus a packet path for
/// coherent rays that share one origin (one laser profile, one range image).

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <utility>

#include "nbs/core/error.hpp"
#include "nbs/mesh/indexed_mesh.hpp"
#include "nbs/sim/ray_caster.hpp"

namespace nbs::embree {

/// How `Scene::cast_fan` traces its rays.
enum class RayMode {
  packet,  ///< rtcIntersect16/8/4, the widest the device supports natively (falls back to single)
  single,  ///< one rtcIntersect1 per ray
};

namespace detail {

[[nodiscard]] inline const char* error_name(RTCError e) {
  switch (e) {
    case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN: return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
  }
  return "unknown RTCError";
}

/// Throws nbs::Error if `device` (may be null) has a pending error; `what` names the failed step.
inline void check(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) throw Error(nbs::detail::concat("Embree: ", what, " failed: ", error_name(e)));
}

/// Packet types and entry points for width N.
template <int N> struct Packet;
template <> struct Packet<4> {
  using type = RTCRayHit4;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, type* r) { rtcIntersect4(v, s, c, r); }
};
template <> struct Packet<8> {
  using type = RTCRayHit8;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, type* r) { rtcIntersect8(v, s, c, r); }
};
template <> struct Packet<16> {
  using type = RTCRayHit16;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, type* r) { rtcIntersect16(v, s, c, r); }
};

}  // namespace detail

/// Owns an RTCDevice and a committed RTCScene holding one triangle geometry (single precision copy of the mesh).
/// Non-copyable, movable (a moved-from Scene may only be destroyed or assigned to). All const members are
/// thread-safe. Models nbs::RayCaster.
class Scene {
public:
  /// Builds the scene. Throws InvalidArgument if the mesh is invalid (empty, non-finite, bad index) or a
  /// coordinate does not fit in a float, nbs::Error if Embree fails.
  explicit Scene(const IndexedMesh& mesh) {
    mesh.validate();
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
      nbs::detail::require(
          (mesh.vertices[i].cwiseAbs().array() < static_cast<double>(std::numeric_limits<float>::max())).all(),
          "mesh vertex ", i, " (", mesh.vertices[i].transpose(), ") does not fit in single precision");
    device_ = rtcNewDevice(nullptr);
    if (device_ == nullptr) detail::check(nullptr, "rtcNewDevice");
    try {
      build(mesh);
    } catch (...) {
      release();
      throw;
    }
  }

  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;
  Scene(Scene&& o) noexcept { swap(o); }
  Scene& operator=(Scene&& o) noexcept {
    if (this != &o) {
      release();
      swap(o);
    }
    return *this;
  }
  ~Scene() { release(); }

  /// First hit along the unit `direction` from `origin` (world frame, metres) with 0 < distance ≤ max_distance;
  /// rtcIntersect1. The normal is the unit (b−a)×(c−a) of the hit triangle, as BruteForceRayCaster reports it.
  [[nodiscard]] std::optional<RayHit> first_hit(const Vec3& origin, const Vec3& direction,
                                                double max_distance = std::numeric_limits<double>::infinity()) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh = make_ray(origin, direction, max_distance);
    rtcIntersect1(scene_, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    return RayHit{rh.ray.tfar, rh.hit.primID, triangle_normal(rh.hit.primID)};
  }

  /// Casts the rays `origin + t·directions[i]`, 0 ≤ t ≤ max_distance, and writes the first-hit distance (metres)
  /// or +inf for a miss to `distances[i]`. `distances.size()` must equal `directions.size()`.
  void cast_fan(const Vec3& origin, std::span<const Vec3> directions, double max_distance, std::span<float> distances,
                RayMode mode = RayMode::packet) const {
    nbs::detail::require(distances.size() == directions.size(), "cast_fan: ", directions.size(), " rays but ",
                         distances.size(), " outputs");
    if (mode == RayMode::single || packet_width_ == 1) return cast_single(origin, directions, max_distance, distances);
    switch (packet_width_) {
      case 16: return cast_packets<16>(origin, directions, max_distance, distances);
      case 8: return cast_packets<8>(origin, directions, max_distance, distances);
      default: return cast_packets<4>(origin, directions, max_distance, distances);
    }
  }

  /// Native packet width used by RayMode::packet: 16, 8, 4, or 1 when the device supports none.
  [[nodiscard]] int packet_width() const { return packet_width_; }
  /// Raw handles, e.g. for benchmarks against plain Embree. Valid while the Scene lives.
  [[nodiscard]] RTCScene handle() const { return scene_; }
  [[nodiscard]] RTCDevice device() const { return device_; }

private:
  void build(const IndexedMesh& mesh) {
    scene_ = rtcNewScene(device_);
    detail::check(device_, "rtcNewScene");
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    detail::check(device_, "rtcNewGeometry");
    vertices_ = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), mesh.vertices.size()));
    triangles_ = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), mesh.triangles.size()));
    if (vertices_ == nullptr || triangles_ == nullptr) {
      rtcReleaseGeometry(geom);
      detail::check(device_, "rtcSetNewGeometryBuffer");
      throw Error("Embree: rtcSetNewGeometryBuffer returned no buffer");
    }
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
      for (int k = 0; k < 3; ++k) vertices_[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      std::copy(mesh.triangles[t].begin(), mesh.triangles[t].end(), triangles_ + 3 * t);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);  // the scene holds the reference now
    rtcCommitScene(scene_);
    detail::check(device_, "building the triangle scene");
    if (rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)) packet_width_ = 16;
    else if (rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)) packet_width_ = 8;
    else if (rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED)) packet_width_ = 4;
    else packet_width_ = 1;
  }

  void release() noexcept {
    if (scene_ != nullptr) rtcReleaseScene(scene_);
    if (device_ != nullptr) rtcReleaseDevice(device_);
    scene_ = nullptr;
    device_ = nullptr;
    vertices_ = nullptr;
    triangles_ = nullptr;
  }

  void swap(Scene& o) noexcept {
    std::swap(device_, o.device_);
    std::swap(scene_, o.scene_);
    std::swap(vertices_, o.vertices_);
    std::swap(triangles_, o.triangles_);
    std::swap(packet_width_, o.packet_width_);
  }

  [[nodiscard]] Vec3 vertex(std::uint32_t i) const {
    return {vertices_[3 * i], vertices_[3 * i + 1], vertices_[3 * i + 2]};
  }
  [[nodiscard]] Vec3 triangle_normal(std::uint32_t t) const {
    const Vec3 a = vertex(triangles_[3 * t]);
    return (vertex(triangles_[3 * t + 1]) - a).cross(vertex(triangles_[3 * t + 2]) - a).normalized();
  }

  [[nodiscard]] static RTCRayHit make_ray(const Vec3& o, const Vec3& d, double max_distance) {
    RTCRayHit rh{};
    rh.ray.org_x = static_cast<float>(o.x());
    rh.ray.org_y = static_cast<float>(o.y());
    rh.ray.org_z = static_cast<float>(o.z());
    rh.ray.dir_x = static_cast<float>(d.x());
    rh.ray.dir_y = static_cast<float>(d.y());
    rh.ray.dir_z = static_cast<float>(d.z());
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = static_cast<float>(max_distance);
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
  }

  void cast_single(const Vec3& origin, std::span<const Vec3> dirs, double max_distance,
                   std::span<float> out) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (std::size_t i = 0; i < dirs.size(); ++i) {
      RTCRayHit rh = make_ray(origin, dirs[i], max_distance);
      rtcIntersect1(scene_, &ctx, &rh);
      out[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity() : rh.ray.tfar;
    }
  }

  template <int N>
  void cast_packets(const Vec3& origin, std::span<const Vec3> dirs, double max_distance,
                    std::span<float> out) const {
    using P = detail::Packet<N>;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) int valid[N];
    typename P::type rh;
    const float ox = static_cast<float>(origin.x()), oy = static_cast<float>(origin.y()),
                oz = static_cast<float>(origin.z()), far = static_cast<float>(max_distance);
    for (std::size_t base = 0; base < dirs.size(); base += N) {
      for (int j = 0; j < N; ++j) {
        const std::size_t i = base + static_cast<std::size_t>(j);
        const bool live = i < dirs.size();
        const Vec3& d = dirs[live ? i : base];
        valid[j] = live ? -1 : 0;
        rh.ray.org_x[j] = ox;
        rh.ray.org_y[j] = oy;
        rh.ray.org_z[j] = oz;
        rh.ray.dir_x[j] = static_cast<float>(d.x());
        rh.ray.dir_y[j] = static_cast<float>(d.y());
        rh.ray.dir_z[j] = static_cast<float>(d.z());
        rh.ray.tnear[j] = 0.0f;
        rh.ray.tfar[j] = far;
        rh.ray.time[j] = 0.0f;
        rh.ray.mask[j] = 0xFFFFFFFFu;
        rh.ray.id[j] = static_cast<unsigned>(j);
        rh.ray.flags[j] = 0;
        rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
      }
      P::intersect(valid, scene_, &ctx, &rh);
      const std::size_t end = std::min(dirs.size(), base + N);
      for (std::size_t i = base; i < end; ++i) {
        const std::size_t j = i - base;
        out[i] = rh.hit.geomID[j] == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity()
                                                              : rh.ray.tfar[j];
      }
    }
  }

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  float* vertices_ = nullptr;             // owned by the geometry (kept alive by the scene)
  std::uint32_t* triangles_ = nullptr;    // idem
  int packet_width_ = 1;
};

static_assert(RayCaster<Scene>);

}  // namespace nbs::embree
