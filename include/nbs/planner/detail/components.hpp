#pragma once
/// \file
/// Every component header the planner composes, included in one place.
///
/// Work-around (remove when fixed upstream): `nbs/candidates/planning_context.hpp` and
/// `nbs/utility/evaluate_candidates.hpp` both define a concept named `nbs::PlanningSpace`, so a translation unit
/// cannot include both. Here the utility's concept is renamed to `nbs::UtilityPlanningSpace` by a macro around its
/// headers. This only works if the utility headers were not included before this header in the same translation
/// unit; include the planner headers first. Once the two concepts have different names the macro changes nothing.

#include "nbs/candidates/boundary_search.hpp"
#include "nbs/candidates/hole_rescan.hpp"
#include "nbs/candidates/replanning.hpp"
#include "nbs/candidates/sphere_generator.hpp"

#define PlanningSpace UtilityPlanningSpace
#include "nbs/utility/evaluate_candidates.hpp"
#include "nbs/utility/selection.hpp"
#include "nbs/utility/thesis_terms.hpp"
#undef PlanningSpace

#include "nbs/mesh/density.hpp"
#include "nbs/mesh/holes.hpp"
#include "nbs/mesh/streaming_mesh.hpp"
#include "nbs/mesh/surface_features.hpp"
#include "nbs/sim/initial_scan_paths.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/termination/criteria.hpp"
#include "nbs/termination/process_control.hpp"
