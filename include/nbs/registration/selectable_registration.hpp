// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// SelectableRegistration: the registration chosen at run time (RuntimePlanner, CLIs, configuration files).

#include <cstdint>
#include <string>
#include <string_view>

#include "nbs/registration/icp.hpp"
#include "nbs/registration/registration.hpp"

namespace nbs {

/// The registration methods of the runtime facade.
enum class RegistrationMethod : std::uint8_t { none, icp };

[[nodiscard]] constexpr std::string_view to_string(RegistrationMethod m) {
  return m == RegistrationMethod::none ? "none" : "icp";
}

/// Parses "none" or "icp"; throws InvalidArgument naming the value otherwise.
[[nodiscard]] inline RegistrationMethod parse_registration_method(std::string_view s) {
  if (s == "none") return RegistrationMethod::none;
  if (s == "icp") return RegistrationMethod::icp;
  throw InvalidArgument(detail::concat("unknown registration method '", s, "'; valid: none, icp"));
}

/// A RegistrationPolicy whose method is a run-time value: `none` behaves as NoRegistration, `icp` as Icp(icp).
struct SelectableRegistration {
  RegistrationMethod method = RegistrationMethod::none;
  IcpSetting icp{};

  template <NormalMesh Mesh>
  [[nodiscard]] RegistrationResult register_scan(const Scan& scan, const Mesh& mesh) const {
    if (method == RegistrationMethod::none) return NoRegistration{}.register_scan(scan, mesh);
    return Icp(icp).register_scan(scan, mesh);
  }
  /// The same for a scan the caller has validated already (see PrevalidatedScan).
  template <NormalMesh Mesh>
  [[nodiscard]] RegistrationResult register_scan(const Scan& scan, const Mesh& mesh, PrevalidatedScan tag) const {
    if (method == RegistrationMethod::none) return NoRegistration{}.register_scan(scan, mesh);
    return Icp(icp).register_scan(scan, mesh, tag);
  }
};

}  // namespace nbs
