// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer target for the PLY readers: read_ply_bytes must throw FileError or return a mesh that passes
// IndexedMesh::validate(); read_ply_points_bytes must throw FileError or return a cloud that passes
// PointCloud::validate(), and when both succeed the cloud's points are the mesh's vertices. Anything else (another
// exception, a crash, a sanitizer report, a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>

#include "nbs/io/read_ply.hpp"
#include "nbs/io/read_ply_points.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  std::optional<nbs::IndexedMesh> mesh;
  try {
    mesh = nbs::read_ply_bytes("fuzz.ply", bytes);
    mesh->validate();
  } catch (const nbs::FileError&) {
  }
  try {
    const nbs::PointCloud cloud = nbs::read_ply_points_bytes("fuzz.ply", bytes);
    cloud.validate();
    if (mesh && cloud.points != mesh->vertices) std::abort();
  } catch (const nbs::FileError&) {
  }
  return 0;
}
