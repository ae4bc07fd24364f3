// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Convenience header: the probabilistic voxel space (Sec. 3.3.2) with both update models.
#include "nbs/space/backend.hpp"
#include "nbs/space/concepts.hpp"
#include "nbs/space/export_ply.hpp"
#include "nbs/space/hashed_block_backend.hpp"
#include "nbs/space/key_slots.hpp"
#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/space/ray_cast.hpp"
#include "nbs/space/ray_traversal.hpp"
#include "nbs/space/surface_features.hpp"
#include "nbs/space/thesis_model.hpp"
#include "nbs/space/unknown_area_grid.hpp"
#include "nbs/space/voxel_key.hpp"
