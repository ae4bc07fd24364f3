// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Convenience header: every core type.
#include "nbs/core/error.hpp"
#include "nbs/core/parameters.hpp"
#include "nbs/core/scan.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/core/types.hpp"
#include "nbs/core/viewpoint.hpp"
