// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Error handling shared by every nbs component.
///
/// Policy: invalid input (non-finite numbers, non-orthonormal rotations, non-positive ranges, malformed files)
/// raises an exception derived from `nbs::Error` *before* any state is modified. The message names the
/// offending parameter and its value.

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace nbs {

/// Base class of every exception nbs throws.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// A parameter or argument is outside its documented domain (NaN, inf, <= 0, ...).
class InvalidArgument : public Error {
public:
  using Error::Error;
};

/// A file could not be read or is not in the expected format.
class FileError : public Error {
public:
  using Error::Error;
};

namespace detail {

/// Formats any streamable values into one string.
template <class... Args>
[[nodiscard]] std::string concat(const Args&... args) {
  std::ostringstream os;
  os.precision(17);
  (os << ... << args);
  return os.str();
}

/// Throws InvalidArgument with the concatenated message unless `ok`.
template <class... Args>
void require(bool ok, const Args&... message) {
  if (!ok) throw InvalidArgument(concat(message...));
}

/// Requires `value` to be finite and strictly positive; `name` appears in the message.
inline void require_positive(std::string_view name, double value) {
  require(std::isfinite(value) && value > 0.0, name, " must be finite and > 0, got ", value);
}

/// Requires `value` to be finite and >= 0.
inline void require_non_negative(std::string_view name, double value) {
  require(std::isfinite(value) && value >= 0.0, name, " must be finite and >= 0, got ", value);
}

/// Requires `lo <= value <= hi` (and finite).
inline void require_in_range(std::string_view name, double value, double lo, double hi) {
  require(std::isfinite(value) && value >= lo && value <= hi, name, " must be in [", lo, ", ", hi, "], got ",
          value);
}

}  // namespace detail
}  // namespace nbs
