// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Tiny JSON formatting helpers for run reports (report.json of nbs_model): numbers that round-trip, `null` for
/// non-finite values (JSON has no NaN/inf), escaped strings, arrays. No parser, no dependency.

#include <cmath>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>

namespace nbs {

/// `v` with 17 significant digits (round-trips through strtod), or `null` if not finite.
[[nodiscard]] inline std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// `s` as a quoted JSON string: `"` and `\` escaped, control characters as \n, \t, ... or \u00XX.
[[nodiscard]] inline std::string json_string(std::string_view s) {
  std::string out = "\"";
  for (char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (ch) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(c));
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

/// `[v0, v1, ...]` with json_number.
[[nodiscard]] inline std::string json_array(std::span<const double> values) {
  std::string out = "[";
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + json_number(values[i]);
  return out + "]";
}

/// `["s0", "s1", ...]` with json_string.
[[nodiscard]] inline std::string json_array(std::span<const std::string> values) {
  std::string out = "[";
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + json_string(values[i]);
  return out + "]";
}

}  // namespace nbs
