// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Convenience header: the mesh concept, the streaming mesh and every mesh analysis.
#include "nbs/mesh/boundaries.hpp"
#include "nbs/mesh/conversion.hpp"
#include "nbs/mesh/density.hpp"
#include "nbs/mesh/holes.hpp"
#include "nbs/mesh/invariants.hpp"
#include "nbs/mesh/mesh_concept.hpp"
#include "nbs/mesh/ply.hpp"
#include "nbs/mesh/streaming_mesh.hpp"
#include "nbs/mesh/surface_features.hpp"
