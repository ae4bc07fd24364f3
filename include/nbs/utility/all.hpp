// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Convenience header: NBS utility (Sec. 4.5.3) — scalars, terms, peer metrics, candidate evaluation, runtime
/// selection.
#include "nbs/utility/candidate_rays.hpp"
#include "nbs/utility/evaluate_candidates.hpp"
#include "nbs/utility/peer_terms.hpp"
#include "nbs/utility/proximity_field.hpp"
#include "nbs/utility/ray_occluder.hpp"
#include "nbs/utility/selection.hpp"
#include "nbs/utility/surface_gain.hpp"
#include "nbs/utility/thesis_terms.hpp"
#include "nbs/utility/utility_function.hpp"
#include "nbs/utility/utility_term.hpp"
#include "nbs/utility/voxel_visit.hpp"
