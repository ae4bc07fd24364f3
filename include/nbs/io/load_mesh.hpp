// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Loads a triangle mesh from PLY, OBJ or STL, chosen by the file's content and name.

#include <cctype>
#include <fstream>
#include <string>

#include "nbs/io/read_obj.hpp"
#include "nbs/io/read_ply.hpp"
#include "nbs/io/read_stl.hpp"

namespace nbs {

/// Loads `path` as PLY if the file starts with the PLY magic line "ply", else as OBJ or STL (binary or ASCII) if its
/// name ends in .obj or .stl (any case), else throws FileError. See read_ply / read_obj / read_stl for the accepted
/// content and the errors.
/// The mesh is returned as stored (no unit conversion); see normalize_on_pedestal.
[[nodiscard]] inline IndexedMesh load_mesh(const std::string& path) {
  std::string magic(4, '\0');
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(detail::concat(path, ": cannot open file"));
    in.read(magic.data(), 4);
    magic.resize(static_cast<std::size_t>(in.gcount()));
  }
  if (magic == "ply\n" || magic == "ply\r") return read_ply(path);
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : std::string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return read_obj(path);
  if (ext == ".stl") return read_stl(path);
  throw FileError(detail::concat(path, ": unknown mesh format (expected a PLY file, a .obj or a .stl file)"));
}

}  // namespace nbs
