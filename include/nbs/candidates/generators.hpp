// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Convenience header: the CandidateGenerator concept and its models (Boundary Search, Hole Rescan, sphere, SEE).
#include "nbs/candidates/boundary_search.hpp"
#include "nbs/candidates/candidate_generator.hpp"
#include "nbs/candidates/hole_rescan.hpp"
#include "nbs/candidates/sphere_generator.hpp"
#include "nbs/candidates/surface_edge_explorer.hpp"
