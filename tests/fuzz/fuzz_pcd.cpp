// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer target for the PCD reader: read_pcd_bytes must throw FileError or return a cloud that passes
// PointCloud::validate(); when the strict read succeeds, the read that drops non-finite points returns the same
// cloud and drops none. Anything else (another exception, a crash, a sanitizer report, a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>

#include "nbs/io/read_pcd.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  std::optional<nbs::PointCloud> strict;
  try {
    strict = nbs::read_pcd_bytes("fuzz.pcd", bytes);
    strict->validate();
  } catch (const nbs::FileError&) {
  }
  nbs::PcdReadOptions drop;
  drop.drop_non_finite = true;
  try {
    const nbs::PointCloud c = nbs::read_pcd_bytes("fuzz.pcd", bytes, drop);
    c.validate();
    if (strict && (c.points != strict->points || c.normals != strict->normals || c.colors != strict->colors ||
                   c.dropped != 0))
      std::abort();
  } catch (const nbs::FileError&) {
    if (strict) std::abort();
  }
  return 0;
}
