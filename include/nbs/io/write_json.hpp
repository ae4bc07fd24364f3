// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Writing a JSON file with nlohmann-json, atomically (temporary file renamed into place).

#include <string>

#include <nlohmann/json.hpp>

#include "nbs/core/error.hpp"
#include "nbs/io/detail/file_bytes.hpp"

namespace nbs {

/// Writes `j.dump(indent)` and a newline to `<path>.tmp`, then renames it to `path`: `path` keeps its old contents or
/// holds the whole document. Doubles round-trip (nlohmann-json prints the shortest form that parses back exactly);
/// non-finite numbers become `null`. `Json` is nlohmann::json (keys sorted) or nlohmann::ordered_json (keys in
/// insertion order). Throws InvalidArgument naming the file if a string is not valid UTF-8 (nothing is written),
/// FileError naming the file if it cannot be written.
template <class Json>
void write_json(const std::string& path, const Json& j, int indent = 2) {
  std::string text;
  try {
    text = j.dump(indent);
  } catch (const nlohmann::json::type_error& e) {
    throw InvalidArgument(detail::concat(path, ": cannot write JSON: ", e.what()));
  }
  text += '\n';
  io_detail::write_file_atomic(path, text);
}

}  // namespace nbs
