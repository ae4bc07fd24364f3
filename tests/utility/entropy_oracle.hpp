// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The binary entropy in bits, written out as the oracle the utility tests compare the library's terms with.

#include <cmath>

namespace nbs_test {
/// H(p) = −p log2 p − (1 − p) log2(1 − p); 0 at p ∈ {0, 1} and outside (0, 1).
inline double H(double p) { return p <= 0.0 || p >= 1.0 ? 0.0 : -p * std::log2(p) - (1 - p) * std::log2(1 - p); }
}  // namespace nbs_test
