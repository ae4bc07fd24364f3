// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Runtime choice of the selection criterion (Sec. 4.7 and the peer metrics of Delmerico et al. 2018) for CLIs and
/// configuration files: a closed enum with short string codes, and `evaluate_selection`, one switch over the
/// precompiled terms.
///
/// | code | criterion | term |
/// |---|---|---|
/// | R | Random | RandomSelection (seeded) |
/// | I | IG: f_utility with ω = 0 (Sec. 4.7) | WeightedUtility |
/// | Q | Quality: f_utility with ω = 1 | WeightedUtility |
/// | C | IG/Quality: f_utility with ω(n_s), Eq. (4.31) | WeightedUtility |
/// | OA | occlusion-aware VI | OcclusionAwareVI |
/// | UV | unobserved-voxel VI | UnobservedVoxelVI |
/// | RSV | rear-side-voxel VI | RearSideVoxelVI |
/// | RSE | rear-side-entropy VI | RearSideEntropyVI |
/// | PC | proximity-count VI | ProximityCountVI |
/// | AE | average-entropy VI | AverageEntropyVI |
/// | VG | Vasquez-Gomez area factor | VasquezGomezVI |
/// | SG | surface gain (ours): Eq. 4.30 with rear-side entropy for e_v, per metre of scan path | SurfaceGain |
/// | SGU | SG plus β × the unseen surface ĉ_m counts as missing that the beams reach (ours) | SurfaceGain, UnseenSurfaceVI |

#include <array>
#include <cctype>
#include <cstdint>
#include <numbers>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/utility/evaluate_candidates.hpp"
#include "nbs/utility/peer_terms.hpp"
#include "nbs/utility/surface_gain.hpp"
#include "nbs/utility/thesis_terms.hpp"

namespace nbs {

enum class Selection {
  random,
  information_gain,
  quality,
  ig_quality,
  occlusion_aware,
  unobserved_voxel,
  rear_side_voxel,
  rear_side_entropy,
  proximity_count,
  average_entropy,
  vasquez_gomez,
  surface_gain,
  surface_gain_unseen,
};

/// Every Selection, in declaration order.
inline constexpr std::array<Selection, 13> kAllSelections{
    Selection::random,          Selection::information_gain, Selection::quality,
    Selection::ig_quality,      Selection::occlusion_aware,  Selection::unobserved_voxel,
    Selection::rear_side_voxel, Selection::rear_side_entropy, Selection::proximity_count,
    Selection::average_entropy, Selection::vasquez_gomez,     Selection::surface_gain,
    Selection::surface_gain_unseen};

/// The string code of `s` (R, I, Q, C, OA, UV, RSV, RSE, PC, AE, VG, SG, SGU).
[[nodiscard]] constexpr std::string_view format_selection(Selection s) {
  switch (s) {
    case Selection::random: return "R";
    case Selection::information_gain: return "I";
    case Selection::quality: return "Q";
    case Selection::ig_quality: return "C";
    case Selection::occlusion_aware: return "OA";
    case Selection::unobserved_voxel: return "UV";
    case Selection::rear_side_voxel: return "RSV";
    case Selection::rear_side_entropy: return "RSE";
    case Selection::proximity_count: return "PC";
    case Selection::average_entropy: return "AE";
    case Selection::vasquez_gomez: return "VG";
    case Selection::surface_gain: return "SG";
    case Selection::surface_gain_unseen: return "SGU";
  }
  return "?";
}

/// Parses a code (case-insensitive, surrounding blanks ignored). Throws InvalidArgument naming the input and the
/// valid codes otherwise.
[[nodiscard]] inline Selection parse_selection(std::string_view code) {
  while (!code.empty() && std::isspace(static_cast<unsigned char>(code.front()))) code.remove_prefix(1);
  while (!code.empty() && std::isspace(static_cast<unsigned char>(code.back()))) code.remove_suffix(1);
  std::string upper(code);
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  std::string valid;
  for (Selection s : kAllSelections) {
    if (upper == format_selection(s)) return s;
    valid += valid.empty() ? "" : ", ";
    valid += format_selection(s);
  }
  throw InvalidArgument(detail::concat("unknown selection criterion '", code, "'; valid codes: ", valid));
}

/// The options of the selection criteria that are not thesis parameters (SelectionSetting::options, and the
/// setting of SelectionUtility / FixedSelection).
struct SelectionOptions {
  double proximity_d_max_m = 0.015;    ///< d_max of PC and VG (metres; 3 voxels of 5 mm)
  bool peers_count_once = false;       ///< apply Sec. 4.5.3's visited marking to the peer VIs
  bool per_metre = true;               ///< SG: divide by the scan path length (+ l_0)
  double length_offset_m = 0.05;       ///< SG: l_0 of the per-metre form (metres, > 0)
  bool surface_gain_modeling = false;  ///< SG, SGU: add ω(n_s)·m_s (SurfaceGain::Setting::modeling)
  double unseen_weight = 16.0;         ///< SGU: β, bits of g_rs per voxel face of unseen surface (≥ 0)
  /// SGU: fan samples with UnseenSample::edge_distance_m below this are left out of g_u (metres, ≥ 0; one voxel of
  /// the default space): they are mostly gaps of the triangulation (spot, scans 8–12: 1–2 % of them by count lie
  /// within 6 mm of missing surface; 32–69 % of the others' area does).
  double unseen_min_edge_distance_m = 0.005;
  bool operator==(const SelectionOptions&) const = default;
};

/// Parameters of every criterion; each uses the fields it needs.
struct SelectionSetting {
  Selection selection = Selection::ig_quality;
  double n_scans = 0.0;                                  ///< n_s for ω(n_s) (C only), ≥ 0
  double n_q = 5.0;                                      ///< n_q of Eq. (4.31)
  double lambda = 0.7;                                   ///< λ of Eq. (4.33)
  double cutoff_rad = 70.0 * std::numbers::pi / 180.0;   ///< incidence cut-off of Eq. (4.33)
  std::uint64_t seed = 0;                                ///< Random
  SelectionOptions options{};                            ///< the options that are not thesis parameters
  /// SGU: where ĉ_m puts the missing surface (UtilityContext::unseen_surface; world, m), borrowed for the call.
  std::span<const UnseenSample> unseen{};
};

/// Evaluates `candidates` with the criterion `sel.selection` (see the table above). N_v is computed from the space
/// (`non_free_voxel_count`); PC and VG build a ProximityField first (included in t_nbs_s).
template <VoxelSpace Space, CandidateRaySensor Sensor>
[[nodiscard]] EvaluationResult evaluate_selection(std::span<const LinearScanPath> candidates, const Sensor& sensor,
                                                  const Space& space, const SelectionSetting& sel,
                                                  const EvaluationSetting& setting = {}) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto thesis = [&](double omega) {
    WeightedUtility::Setting w;
    w.non_free_voxels = non_free_voxel_count(space);
    w.omega = omega;
    w.lambda = sel.lambda;
    w.cutoff_rad = sel.cutoff_rad;
    return evaluate_candidates(candidates, sensor, space, WeightedUtility(w), setting);
  };
  const PeerTermSetting peer{sel.options.peers_count_once};
  EvaluationResult r;
  switch (sel.selection) {
    case Selection::random: r = evaluate_candidates(candidates, sensor, space, RandomSelection({sel.seed}), setting); break;
    case Selection::information_gain: r = thesis(0.0); break;
    case Selection::quality: r = thesis(1.0); break;
    case Selection::ig_quality: r = thesis(modeling_weight(sel.n_scans, sel.n_q)); break;
    case Selection::occlusion_aware: r = evaluate_candidates(candidates, sensor, space, OcclusionAwareVI(peer), setting); break;
    case Selection::unobserved_voxel: r = evaluate_candidates(candidates, sensor, space, UnobservedVoxelVI(peer), setting); break;
    case Selection::rear_side_voxel: r = evaluate_candidates(candidates, sensor, space, RearSideVoxelVI(peer), setting); break;
    case Selection::rear_side_entropy: r = evaluate_candidates(candidates, sensor, space, RearSideEntropyVI(peer), setting); break;
    case Selection::average_entropy:
      r = evaluate_candidates(candidates, sensor, space, AverageEntropyVI({sel.options.peers_count_once, false}),
                              setting);
      break;
    case Selection::proximity_count: {
      const ProximityField field = ProximityField::build(space, sel.options.proximity_d_max_m);
      r = evaluate_candidates(candidates, sensor, space, ProximityCountVI(field, peer), setting);
      break;
    }
    case Selection::vasquez_gomez: {
      const ProximityField field = ProximityField::build(space, sel.options.proximity_d_max_m);
      r = evaluate_candidates(candidates, sensor, space, VasquezGomezVI(field), setting);
      break;
    }
    case Selection::surface_gain:
    case Selection::surface_gain_unseen: {
      SurfaceGain::Setting g;
      g.non_free_voxels = non_free_voxel_count(space);
      g.omega = modeling_weight(sel.n_scans, sel.n_q);
      g.lambda = sel.lambda;
      g.cutoff_rad = sel.cutoff_rad;
      g.length_offset_m = sel.options.length_offset_m;
      g.modeling = sel.options.surface_gain_modeling;
      const bool unseen = sel.selection == Selection::surface_gain_unseen;
      g.unseen_weight = unseen ? sel.options.unseen_weight : 0.0;
      const UnseenSurfaceMap map = unseen ? UnseenSurfaceMap::build(sel.unseen, space.grid(),
                                                                    sel.options.unseen_min_edge_distance_m)
                                          : UnseenSurfaceMap();
      std::vector<double> lengths;
      if (sel.options.per_metre) {
        lengths.reserve(candidates.size());
        for (const LinearScanPath& c : candidates) lengths.push_back(c.length());
      }
      r = evaluate_candidates(candidates, sensor, space, SurfaceGain(g, lengths, &map), setting);
      break;
    }
  }
  r.t_nbs_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace nbs
