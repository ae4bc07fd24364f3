// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer target: read_obj_bytes must throw FileError or return a mesh that passes IndexedMesh::validate().
#include <cstddef>
#include <cstdint>
#include <string>

#include "nbs/io/read_obj.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const nbs::IndexedMesh m = nbs::read_obj_bytes("fuzz.obj", std::string(reinterpret_cast<const char*>(data), size));
    m.validate();
  } catch (const nbs::FileError&) {
  }
  return 0;
}
