// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Strict access to the JSON manifest of a recorded session (docs/session-format.md): every accessor names the file
/// and the key path (e.g. `scans[2].pose_per`) and the value it rejects.

#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs::io_detail {

/// A key path inside one JSON file, for messages: "<file>: <path>".
struct JsonWhere {
  const std::string& file;
  std::string path;
  [[nodiscard]] JsonWhere operator[](std::string_view key) const {
    return {file, path.empty() ? std::string(key) : path + "." + std::string(key)};
  }
  [[nodiscard]] JsonWhere at(std::size_t i) const { return {file, detail::concat(path, "[", i, "]")}; }
  template <class... Args>
  [[noreturn]] void fail(const Args&... what) const {
    throw FileError(detail::concat(file, ": ", path, " ", what...));
  }
};

/// `j[key]`, which must exist (FileError naming the key otherwise).
[[nodiscard]] inline const nlohmann::json& json_member(const nlohmann::json& j, std::string_view key,
                                                       const JsonWhere& where) {
  if (!j.is_object()) where.fail("must be an object, got ", j.type_name());
  const auto it = j.find(key);
  if (it == j.end()) where[key].fail("is missing");
  return *it;
}

[[nodiscard]] inline std::string json_string(const nlohmann::json& j, const JsonWhere& where) {
  if (!j.is_string()) where.fail("must be a string, got ", j.dump());
  return j.get<std::string>();
}

[[nodiscard]] inline double json_finite(const nlohmann::json& j, const JsonWhere& where) {
  if (!j.is_number()) where.fail("must be a number, got ", j.dump());
  const double v = j.get<double>();
  if (!std::isfinite(v)) where.fail("must be finite, got ", v);
  return v;
}

[[nodiscard]] inline std::uint64_t json_count(const nlohmann::json& j, const JsonWhere& where) {
  if (!j.is_number_unsigned()) where.fail("must be a non-negative integer, got ", j.dump());
  return j.get<std::uint64_t>();
}

/// An array of exactly `n` finite numbers.
template <std::size_t N>
[[nodiscard]] std::array<double, N> json_numbers(const nlohmann::json& j, const JsonWhere& where) {
  if (!j.is_array() || j.size() != N) where.fail("must be an array of ", N, " numbers, got ", j.dump());
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = json_finite(j[i], where.at(i));
  return out;
}

[[nodiscard]] inline Vec3 json_vec3(const nlohmann::json& j, const JsonWhere& where, double scale = 1.0) {
  const auto v = json_numbers<3>(j, where);
  return scale * Vec3(v[0], v[1], v[2]);
}

/// A rigid pose stored as its 3×4 block, row-major (as the pose files); translation × `scale`.
[[nodiscard]] inline Pose json_pose(const nlohmann::json& j, const JsonWhere& where, double scale = 1.0) {
  const auto v = json_numbers<12>(j, where);
  Pose T = Pose::Identity();
  for (int k = 0; k < 12; ++k) T.matrix()(k / 4, k % 4) = (k % 4 == 3) ? v[static_cast<std::size_t>(k)] * scale
                                                                       : v[static_cast<std::size_t>(k)];
  if (std::string why = pose_problem(T); !why.empty()) where.fail("is not a rigid pose: ", why);
  return T;
}

[[nodiscard]] inline nlohmann::json pose_json(const Pose& T) {
  nlohmann::json a = nlohmann::json::array();
  for (int k = 0; k < 12; ++k) a.push_back(T.matrix()(k / 4, k % 4));
  return a;
}

[[nodiscard]] inline nlohmann::json vec3_json(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

/// Rejects keys of `j` that are not in `known` (a misspelt optional key must not be ignored silently).
inline void json_known_keys(const nlohmann::json& j, std::initializer_list<std::string_view> known,
                            const JsonWhere& where) {
  for (const auto& [key, value] : j.items()) {
    bool ok = false;
    for (std::string_view k : known) ok = ok || key == k;
    if (!ok) {
      std::string list;
      for (std::string_view k : known) (list += list.empty() ? "" : ", ") += k;
      where[key].fail("is not a known key (known: ", list, ")");
    }
  }
}

}  // namespace nbs::io_detail
