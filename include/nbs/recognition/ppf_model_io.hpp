// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The precomputed PPF feature table of a database model as a binary file (format version 1, little-endian):
///
///     magic NBSPPF1 + line feed (8 bytes) | u32 version = 1 | u32 0 (reserved)
///     f64 distance_step_ratio | f64 angle_step_rad | u64 max_points | f64 diameter_m
///     u64 n_points | u64 n_keys | u64 n_entries
///     n_points × 6 f64 (x y z nx ny nz, model frame) | n_keys × u64 key | (n_keys + 1) × u32 offset
///     n_entries × (u32 reference, f32 alpha_m) | u64 FNV-1a 64 of every byte before it
///
/// Written atomically (temporary file renamed into place); read with every field checked.

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "nbs/core/error.hpp"
#include "nbs/io/detail/file_bytes.hpp"
#include "nbs/recognition/ppf_model.hpp"

namespace nbs {

inline constexpr std::uint32_t kPpfTableVersion = 1;

namespace ppf_io_detail {
inline constexpr std::string_view kMagic{"NBSPPF1\n", 8};

[[nodiscard]] inline std::uint64_t fnv1a(std::string_view bytes) {
  std::uint64_t h = 14695981039346656037ULL;
  for (const char c : bytes) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ULL;
  return h;
}

template <class T>
void put(std::string& out, T v) {
  static_assert(std::endian::native == std::endian::little, "the PPF table format is little-endian");
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

/// Reads fixed-size fields, throwing FileError naming the file past the end.
struct Reader {
  const std::string& path;
  std::string_view bytes;
  std::size_t at = 0;
  template <class T>
  T get(std::string_view what) {
    if (bytes.size() - at < sizeof(T))
      throw FileError(detail::concat(path, ": PPF table truncated at byte ", at, " (reading ", what, ")"));
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof(T));
    at += sizeof(T);
    return v;
  }
};
}  // namespace ppf_io_detail

/// Writes `model`'s table to `path` (format above) via `<path>.tmp`: `path` keeps its old contents or holds the
/// whole table. Throws FileError naming the file if it cannot be written.
inline void write_ppf_model(const std::string& path, const PpfModel& model) {
  using ppf_io_detail::put;
  const PpfModel::Table t = model.table();
  std::string out(ppf_io_detail::kMagic);
  put(out, kPpfTableVersion);
  put(out, std::uint32_t{0});
  put(out, t.setting.distance_step_ratio);
  put(out, t.setting.angle_step_rad);
  put(out, static_cast<std::uint64_t>(t.setting.max_points));
  put(out, t.diameter_m);
  put(out, static_cast<std::uint64_t>(t.points.size()));
  put(out, static_cast<std::uint64_t>(t.keys.size()));
  put(out, static_cast<std::uint64_t>(t.entries.size()));
  for (std::size_t i = 0; i < t.points.size(); ++i)
    for (const Vec3* v : {&t.points.points[i], &t.points.normals[i]})
      for (int k = 0; k < 3; ++k) put(out, (*v)[k]);
  for (const std::uint64_t k : t.keys) put(out, k);
  for (const std::uint32_t o : t.offsets) put(out, o);
  for (const PpfEntry& e : t.entries) put(out, e.reference), put(out, e.alpha);
  put(out, ppf_io_detail::fnv1a(out));
  io_detail::write_file_atomic(path, out);
}

/// Reads a table written by write_ppf_model. Throws FileError naming the file if it cannot be read, its magic or
/// version differs, its length does not match its counts, its checksum differs (a corrupted byte), or the table is
/// inconsistent (PpfModel(Table)'s checks; the message names the file).
[[nodiscard]] inline PpfModel read_ppf_model(const std::string& path) {
  const std::string bytes = io_detail::read_file_bytes(path);
  if (bytes.size() < 16 || std::string_view(bytes).substr(0, 8) != ppf_io_detail::kMagic)
    throw FileError(detail::concat(path, ": not an nbs PPF table (bad magic)"));
  ppf_io_detail::Reader r{path, bytes, 8};
  const auto version = r.get<std::uint32_t>("version");
  if (version != kPpfTableVersion)
    throw FileError(detail::concat(path, ": PPF table format version ", version, ", this build reads version ",
                                   kPpfTableVersion));
  (void)r.get<std::uint32_t>("reserved");
  PpfModel::Table t;
  t.setting.distance_step_ratio = r.get<double>("distance_step_ratio");
  t.setting.angle_step_rad = r.get<double>("angle_step_rad");
  t.setting.max_points = r.get<std::uint64_t>("max_points");
  t.diameter_m = r.get<double>("diameter_m");
  const auto n = r.get<std::uint64_t>("n_points"), nk = r.get<std::uint64_t>("n_keys"),
             ne = r.get<std::uint64_t>("n_entries");
  const std::uint64_t size = bytes.size();
  const std::uint64_t expected =
      n > size || nk > size || ne > size ? 0 : r.at + 48 * n + 12 * nk + 4 + 8 * ne + 8;  // counts ≤ size: no overflow
  if (expected != bytes.size())
    throw FileError(detail::concat(path, ": PPF table of ", bytes.size(), " bytes, its counts (", n, " points, ", nk,
                                   " keys, ", ne, " entries) need ", expected));
  const std::uint64_t stored = [&] {
    std::uint64_t v;
    std::memcpy(&v, bytes.data() + bytes.size() - 8, 8);
    return v;
  }();
  if (stored != ppf_io_detail::fnv1a(std::string_view(bytes).substr(0, bytes.size() - 8)))
    throw FileError(detail::concat(path, ": PPF table checksum mismatch (the file is corrupted)"));
  t.points.points.resize(n);
  t.points.normals.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    for (Vec3* v : {&t.points.points[i], &t.points.normals[i]})
      for (int k = 0; k < 3; ++k) (*v)[k] = r.get<double>("points");
  t.keys.resize(nk);
  for (auto& k : t.keys) k = r.get<std::uint64_t>("keys");
  t.offsets.resize(nk + 1);
  for (auto& o : t.offsets) o = r.get<std::uint32_t>("offsets");
  t.entries.resize(ne);
  for (auto& e : t.entries) e.reference = r.get<std::uint32_t>("entries"), e.alpha = r.get<float>("entries");
  try {
    return PpfModel(std::move(t));
  } catch (const InvalidArgument& e) {
    throw FileError(detail::concat(path, ": ", e.what()));
  }
}

}  // namespace nbs
