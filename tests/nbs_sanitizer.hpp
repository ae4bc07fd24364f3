// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Test helper: whether this executable is compiled with AddressSanitizer. gcc defines __SANITIZE_ADDRESS__, clang 14
// only answers __has_feature(address_sanitizer). Long loops run shorter under the sanitizers (time), which checks
// memory safety, not the targets.

namespace nbs_test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif

}  // namespace nbs_test
