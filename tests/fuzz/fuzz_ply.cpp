// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer target: read_ply_bytes must throw FileError or return a mesh that passes IndexedMesh::validate();
// anything else (another exception, a crash, a sanitizer report, a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "nbs/io/read_ply.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const nbs::IndexedMesh m = nbs::read_ply_bytes("fuzz.ply", std::string(reinterpret_cast<const char*>(data), size));
    m.validate();
  } catch (const nbs::FileError&) {
  }
  return 0;
}
