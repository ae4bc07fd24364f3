// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Umbrella header of the ground-truth metrics (Sec. 4.7.2, Tab. 5.2): surface samples, c_a / c_b, c_obs, ē, l_s,
/// and the 13 initial scan paths.

#include "nbs/sim/completeness.hpp"
#include "nbs/sim/ground_truth.hpp"
#include "nbs/sim/initial_scan_paths.hpp"
#include "nbs/sim/mesh_distance.hpp"
#include "nbs/sim/observability.hpp"
#include "nbs/sim/point_triangle_distance.hpp"
#include "nbs/sim/scan_path_length.hpp"
#include "nbs/sim/surface_color.hpp"
#include "nbs/sim/surface_samples.hpp"
