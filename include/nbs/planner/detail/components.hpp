// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Every component header the planner composes, included in one place.

#include "nbs/candidates/boundary_search.hpp"
#include "nbs/candidates/hole_rescan.hpp"
#include "nbs/candidates/replanning.hpp"
#include "nbs/candidates/sphere_generator.hpp"
#include "nbs/candidates/surface_edge_explorer.hpp"

#include "nbs/utility/evaluate_candidates.hpp"
#include "nbs/utility/selection.hpp"
#include "nbs/utility/thesis_terms.hpp"

#include "nbs/coverage/coverage_estimator.hpp"
#include "nbs/mesh/density.hpp"
#include "nbs/mesh/holes.hpp"
#include "nbs/mesh/streaming_mesh.hpp"
#include "nbs/mesh/surface_features.hpp"
#include "nbs/sim/initial_scan_paths.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/termination/criteria.hpp"
#include "nbs/termination/process_control.hpp"
