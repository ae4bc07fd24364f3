// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Scan candidate (Sec. 4.3): a linear scan path plus where it came from and which surface it is meant to see.

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "nbs/core/scan_path.hpp"

namespace nbs {

/// Which generator produced a candidate.
enum class CandidateSource : std::uint8_t {
  boundary_search,  ///< Sec. 4.2–4.3
  hole_rescan,      ///< Sec. 4.4, Alg. 2
  sphere,           ///< sphere baseline, Sec. 4.7.2
  surface_edge,     ///< SEE peer planner (surface_edge_explorer.hpp)
};

/// A surface point the candidate is planned to measure, world frame; `normal` is unit and points to the sensor side.
/// Utility evaluation and the occlusion test of Alg. 3 (Sec. 4.5.2) cast rays towards these points.
struct SurfaceTarget {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
};

/// One scan candidate. `path.start()` carries the orientation; the path moves along its s_y (zero length for area
/// sensors). Invariant (all generators): `aim` lies at distance d_s along s_z from the path line, i.e.
/// (aim − s_p¹)·s_z = d_s and aim − s_p¹ − d_s·s_z ∥ s_y. `aim` is the pivot for the rotations of Alg. 3.
struct ScanCandidate {
  LinearScanPath path;
  CandidateSource source = CandidateSource::boundary_search;
  std::size_t index = 0;              ///< boundary index (detect_boundaries order), hole index, or sphere path index.
  std::vector<std::size_t> merged;    ///< Hole Rescan: every hole this (combined) path covers; else empty.
  SurfaceTarget aim;                  ///< p of Eq. 4.18 / c_h of Eqs. 4.22–4.23 / sphere centre side.
  std::vector<SurfaceTarget> targets; ///< points along d_b (boundaries) or d_h (holes), world frame.
  double overlap = 0.0;               ///< Boundary Search: o of Eq. 4.14 actually reached (0 for other sources).
  bool sharp_corner = false;          ///< Boundary Search: rotated about the boundary (Sec. 4.3.1, Fig. 4.7).
};

/// Why a generator returned what it returned. Everything except `ok` comes with an empty candidate list.
enum class CandidateStatus : std::uint8_t {
  ok,               ///< at least one candidate
  empty_mesh,       ///< the mesh has no triangle (nothing of the object seen yet, Sec. 4.1)
  no_boundaries,    ///< Alg. 1 found no boundary in the last scan
  no_holes,         ///< no hole with h_min ≤ |E_H| ≤ h_max
  all_rejected,     ///< boundaries/holes exist but none gave a candidate (fit failed, every direction occluded)
  empty_unknown_area,  ///< sphere baseline: the bounding box of the unknown area is empty
  no_frontier,      ///< SEE: no measured point is a frontier point
};

[[nodiscard]] constexpr std::string_view to_string(CandidateStatus s) {
  switch (s) {
    case CandidateStatus::ok: return "ok";
    case CandidateStatus::empty_mesh: return "empty mesh: no triangle yet";
    case CandidateStatus::no_boundaries: return "no boundary detected in the last scan";
    case CandidateStatus::no_holes: return "no hole of interest (h_min..h_max edges)";
    case CandidateStatus::all_rejected: return "every boundary/hole was rejected";
    case CandidateStatus::empty_unknown_area: return "the bounding box of the unknown area is empty";
    case CandidateStatus::no_frontier: return "no frontier point (SEE)";
  }
  return "unknown status";
}

/// Result of one generator call. `considered` boundaries/holes/paths; `rejected` of them gave no candidate.
struct CandidateSet {
  std::vector<ScanCandidate> candidates;
  CandidateStatus status = CandidateStatus::ok;
  std::size_t considered = 0;  ///< boundaries / holes / sphere paths looked at
  std::size_t rejected = 0;    ///< of them given no candidate (occluded, degenerate, ...)
  std::size_t measured = 0;    ///< of them skipped as measured surface (Hole Rescan, skip_measured_holes)
};

}  // namespace nbs
