// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Candidate evaluation (Sec. 4.5.3): simulate each scan candidate's beams in the voxel space, feed the visited
/// voxels to a UtilityTerm, return every candidate's utility and the best one. Parallel over candidates with
/// std::thread; each candidate is evaluated entirely by one thread with its own copy of the term and its own
/// visited set, so the values are bit-identical for any thread count.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <limits>
#include <span>
#include <thread>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/scan_path.hpp"
#include "nbs/utility/candidate_rays.hpp"
#include "nbs/utility/detail/key_set.hpp"
#include "nbs/utility/detail/planning_snapshot.hpp"
#include "nbs/utility/ray_occluder.hpp"
#include "nbs/utility/utility_term.hpp"

namespace nbs {

/// Coarse-to-fine evaluation, our addition to the beam sub-sampling of Sec. 4.5.3 (the thesis scores every candidate
/// with every 4th beam row and column): a first pass scores every candidate with both strides of the evaluation's
/// `sampling` multiplied by `coarse_factor`; the `refine_top` best of that pass (ties: lower index, NaN never) are
/// scored again with `sampling`, and the best is chosen among those only. Deterministic: both passes are per
/// candidate, so the choice does not depend on the thread count. With `coarse_factor` 1, or at most `refine_top`
/// candidates, there is one pass with `sampling` (no refinement). Terms that need no rays always take one pass.
struct CoarseToFine {
  std::size_t coarse_factor = 1;  ///< stride multiplier of the first pass, ≥ 1 (1 = off)
  std::size_t refine_top = 16;    ///< candidates re-scored with the full `sampling`, ≥ 1
  void validate() const {
    detail::require(coarse_factor >= 1, "CoarseToFine.coarse_factor must be >= 1, got ", coarse_factor);
    detail::require(refine_top >= 1, "CoarseToFine.refine_top must be >= 1, got ", refine_top);
  }
  [[nodiscard]] bool active(std::size_t candidates) const { return coarse_factor > 1 && candidates > refine_top; }
  /// `fine` with both strides multiplied by coarse_factor (saturating at SIZE_MAX).
  [[nodiscard]] RaySampling coarse(const RaySampling& fine) const {
    const auto mul = [&](std::size_t s) {
      return s > std::numeric_limits<std::size_t>::max() / coarse_factor ? std::numeric_limits<std::size_t>::max()
                                                                         : s * coarse_factor;
    };
    return {mul(fine.profile_stride), mul(fine.ray_stride)};
  }
};

/// How evaluate_candidates runs. Not an aggregate (so `{threads, sampling}` keeps working as fields are added).
struct EvaluationSetting {
  EvaluationSetting() = default;
  EvaluationSetting(unsigned threads_, RaySampling sampling_, CoarseToFine refine_ = {})
      : threads(threads_), sampling(sampling_), refine(refine_) {}
  unsigned threads = 0;        ///< worker threads; 0 = std::thread::hardware_concurrency()
  RaySampling sampling;        ///< beam sub-sampling (Sec. 4.5.3)
  CoarseToFine refine;         ///< coarse-to-fine evaluation; off by default (coarse_factor 1)
  /// Surface features per voxel (Sec. 4.5.1) that VoxelVisit::features points into (the planner owns them);
  /// nullptr = none (terms that need them, e.g. SurfaceQuality, then see no surface). Borrowed for the call.
  const SurfaceFeatureMap* features = nullptr;
  /// Occlusion by what lies outside the space (ray_occluder.hpp); empty = none. Each simulated beam is cut where
  /// the occluder says and ends with RayEnd::occluded (a term sees a cut beam as one that met nothing beyond its
  /// voxels; e.g. VasquezGomezVI counts it as a ray that registers nothing, as one that misses the object).
  RayOccluder occluder;
};

enum class EvaluationStatus {
  ok,             ///< values and best are set
  no_candidates,  ///< the candidate list was empty; best == npos
};

/// Per-candidate utilities and the choice. Sizes of the vectors equal the number of candidates.
struct EvaluationResult {
  static constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();
  EvaluationStatus status = EvaluationStatus::no_candidates;
  std::vector<double> values;          ///< utility of each candidate (higher is better)
  std::vector<std::uint64_t> rays;     ///< simulated rays per candidate
  std::vector<std::uint64_t> voxels;   ///< voxel visits per candidate (repeated visits included)
  /// 1 if values[i] (and rays[i], voxels[i]) come from the full `sampling`; 0 if only from the coarse pass of
  /// CoarseToFine (then best is never i). All 1 without refinement.
  std::vector<std::uint8_t> refined;
  /// Index of the largest value; ties go to the lower index; NaN values are never chosen; npos if none.
  std::size_t best = npos;
  double t_nbs_s = 0.0;                ///< wall-clock time of the evaluation, seconds
  unsigned threads = 0;                ///< threads actually used
  [[nodiscard]] bool ok() const { return status == EvaluationStatus::ok && best != npos; }
};

/// Index of the largest non-NaN value (ties: lower index), or EvaluationResult::npos.
[[nodiscard]] inline std::size_t best_index(std::span<const double> values) {
  std::size_t best = EvaluationResult::npos;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isnan(values[i]) && (best == EvaluationResult::npos || values[i] > values[best])) best = i;
  return best;
}

/// Indices of the (at most) k largest non-NaN values, largest first, ties to the lower index.
[[nodiscard]] inline std::vector<std::size_t> top_indices(std::span<const double> values, std::size_t k) {
  std::vector<std::size_t> idx;
  idx.reserve(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isnan(values[i])) idx.push_back(i);
  const auto before = [&](std::size_t a, std::size_t b) { return values[a] > values[b] || (values[a] == values[b] && a < b); };
  const std::size_t m = std::min(k, idx.size());
  std::partial_sort(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(m), idx.end(), before);
  idx.resize(m);
  return idx;
}

namespace detail {

/// Per-thread scratch buffers of the evaluator, reused across candidates.
struct EvaluationBuffers {
  std::vector<Ray> rays;
  KeySet visited;       // fallback path (no snapshot)
  VisitedBits bits;     // snapshot path: one bit per voxel of the box
};

/// Evaluates one candidate with `term` (reset by begin_candidate). With an enabled `snapshot`, rays are cast over it
/// (the voxels, order and stop rule of space.cast_ray, see planning_snapshot.hpp); otherwise through
/// space.cast_ray with per-voxel lookups. Both feed the term the same VoxelVisits; over the snapshot, a term that
/// ignores repeated visits (visits_first_only) gets only the first ones (cast_first_visits).
template <VoxelSpace Space, CandidateRaySensor Sensor, UtilityTerm Term>
void evaluate_one(std::size_t index, const LinearScanPath& path, const Sensor& sensor, const Space& space,
                  const PlanningSnapshot<Space>& snapshot, const SurfaceFeatureMap* features,
                  const RaySampling& sampling, const RayOccluder* occluder, Term& term, EvaluationBuffers& buf,
                  double& value,
                  std::uint64_t& ray_count, std::uint64_t& voxel_count) {
  using State = typename Space::State;
  term.begin_candidate(index);
  ray_count = voxel_count = 0;
  if constexpr (term_needs_rays<Term>()) {
    buf.rays.clear();
    append_candidate_rays(path, sensor, sampling, buf.rays);
    const bool fast = snapshot.enabled();
    if (fast) buf.bits.reset(snapshot.voxel_count());
    buf.visited.clear();
    const auto& model = space.model();
    const bool have_features = features != nullptr && features->size() > 0;
    const VoxelGrid& grid = space.grid();
    const bool first_only = fast && visits_first_only(term);
    for (Ray& ray : buf.rays) {
      if (occluder || fast) {
        detail::require(ray.origin.allFinite() && ray.end.allFinite(), "candidate ", index, ": ray is not finite");
      }
      const Vec3 dir = (ray.end - ray.origin).normalized();
      bool cut = false;
      if (occluder) {
        const double f = (*occluder)(ray);
        detail::require(f >= 0.0 && f <= 1.0, "candidate ", index, ": the ray occluder returned ", f,
                        ", not a fraction in [0, 1]");
        if (f < 1.0) {
          cut = true;
          ray.end = ray.origin + f * (ray.end - ray.origin);
          if (!(f > 0.0)) {  // occluded at its origin: nothing to cast
            term.begin_ray();
            term.end_ray(RayEnd{false, 0, true});
            continue;
          }
        }
      }
      std::uint32_t n = 0;
      const auto emit_at = [&](const VoxelKey& k, const VoxelClass& c, bool first_visit, std::uint32_t at) {
        VoxelVisit v;
        v.key = k;
        v.probability = c.probability;
        v.entropy_bits = c.entropy_bits;
        v.occupied = c.occupied;
        v.observed = c.observed;
        v.first_visit = first_visit;
        v.features = c.features;
        v.direction = dir;
        v.distance_m = (grid.center(k) - ray.origin).norm();
        v.index = at;
        term.visit(v);
      };
      const auto emit = [&](const VoxelKey& k, const VoxelClass& c, bool first_visit) { emit_at(k, c, first_visit, n++); };
      term.begin_ray();
      RaycastResult res;
      typename PlanningSnapshot<Space>::Clipped clipped;
      if (fast) clipped = snapshot.clip(ray);
      if (first_only && clipped.meets && clipped.inside) {
        res = snapshot.cast_first_visits(clipped, buf.bits, [&](const VoxelKey& k, const VoxelClass& c, std::uint32_t at) {
          emit_at(k, c, true, at);
        });
      } else if (fast && clipped.meets && clipped.inside) {
        res = snapshot.cast(clipped, [&](const VoxelKey& k, const VoxelClass& c, std::size_t box_index) {
          emit(k, c, buf.bits.insert(box_index));
          return true;
        });
      } else if (!fast || clipped.meets) {
        res = space.cast_ray(ray, [&](const VoxelKey& k, const State& s) {
          VoxelClass c;
          c.probability = model.probability(s);
          c.entropy_bits = -1.0;  // computed by VoxelVisit::entropy() if a term asks
          c.occupied = model.occupied(s);
          if constexpr (std::equality_comparable<State>) {
            c.observed = !(s == State{}) || space.observed(k);  // only unknown-looking states need the lookup
          } else {
            c.observed = space.observed(k);
          }
          // Features exist only for surface voxels (p ≥ Parameters::occupied_threshold, Sec. 4.5.1), which are occupied; look up only those.
          c.features = (have_features && c.occupied) ? features->find(k) : nullptr;
          emit(k, c, snapshot.contains(k) ? buf.bits.insert(snapshot.index_of(k)) : buf.visited.insert(k.pack()));
          return true;
        });
      }
      term.end_ray(RayEnd{res.hit, res.voxels, cut && !res.hit});
      voxel_count += res.voxels;
    }
    ray_count = buf.rays.size();
  }
  value = static_cast<double>(term.value());
}

}  // namespace detail

/// Evaluates every candidate scan path with a copy of `prototype` and returns the utilities and the best index
/// (status no_candidates for an empty list). The sensor is validated first; invalid input throws InvalidArgument
/// (the lowest-index candidate's error if several fail). Thread-safety: `space` is only read; do not integrate
/// into it concurrently.
template <VoxelSpace Space, CandidateRaySensor Sensor, UtilityTerm Term>
[[nodiscard]] EvaluationResult evaluate_candidates(std::span<const LinearScanPath> candidates, const Sensor& sensor,
                                                   const Space& space, const Term& prototype,
                                                   const EvaluationSetting& setting = {}) {
  const auto t0 = std::chrono::steady_clock::now();
  setting.sampling.validate();
  setting.refine.validate();
  sensor.validate();
  EvaluationResult r;
  const std::size_t n = candidates.size();
  r.values.assign(n, 0.0);
  r.rays.assign(n, 0);
  r.voxels.assign(n, 0);
  r.refined.assign(n, 1);
  if (n == 0) {
    r.status = EvaluationStatus::no_candidates;
    r.t_nbs_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }
  unsigned threads = setting.threads == 0 ? std::max(1u, std::thread::hardware_concurrency()) : setting.threads;
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, n));
  r.threads = threads;

  std::vector<std::exception_ptr> errors(n);
  const detail::PlanningSnapshot<Space> snapshot =
      term_needs_rays<Term>() ? detail::PlanningSnapshot<Space>(space, setting.features) : detail::PlanningSnapshot<Space>();
  // Scores candidates[order[j]] for every j (all candidates if order is empty) with `sampling`.
  const auto pass = [&](std::span<const std::size_t> order, const RaySampling& sampling) {
    const std::size_t m = order.empty() ? n : order.size();
    std::atomic<std::size_t> next{0};
    const auto worker = [&] {
      Term term = prototype;
      detail::EvaluationBuffers buf;
      for (std::size_t j; (j = next.fetch_add(1, std::memory_order_relaxed)) < m;) {
        const std::size_t i = order.empty() ? j : order[j];
        try {
          detail::evaluate_one(i, candidates[i], sensor, space, snapshot, setting.features, sampling,
                               setting.occluder ? &setting.occluder : nullptr, term, buf,
                               r.values[i], r.rays[i], r.voxels[i]);
        } catch (...) {
          errors[i] = std::current_exception();
        }
      }
    };
    const unsigned t = static_cast<unsigned>(std::min<std::size_t>(threads, m));
    if (t <= 1) {
      worker();
    } else {
      std::vector<std::thread> pool;
      pool.reserve(t);
      for (unsigned k = 0; k < t; ++k) pool.emplace_back(worker);
      for (auto& th : pool) th.join();
    }
    for (auto& e : errors)
      if (e) std::rethrow_exception(e);
  };
  if (term_needs_rays<Term>() && setting.refine.active(n)) {
    pass({}, setting.refine.coarse(setting.sampling));
    const std::vector<std::size_t> top = top_indices(r.values, setting.refine.refine_top);
    r.refined.assign(n, 0);
    for (std::size_t i : top) r.refined[i] = 1;
    if (!top.empty()) pass(top, setting.sampling);
    std::vector<double> fine(n, std::numeric_limits<double>::quiet_NaN());
    for (std::size_t i : top) fine[i] = r.values[i];
    r.best = best_index(fine);
  } else {
    pass({}, setting.sampling);
    r.best = best_index(r.values);
  }
  r.status = EvaluationStatus::ok;
  r.t_nbs_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

/// Convenience overload for a vector of candidates.
template <VoxelSpace Space, CandidateRaySensor Sensor, UtilityTerm Term>
[[nodiscard]] EvaluationResult evaluate_candidates(const std::vector<LinearScanPath>& candidates, const Sensor& sensor,
                                                   const Space& space, const Term& prototype,
                                                   const EvaluationSetting& setting = {}) {
  return evaluate_candidates(std::span<const LinearScanPath>(candidates), sensor, space, prototype, setting);
}

/// N_v of Eqs. (4.32)/(4.34): voxels overlapping the space's bounding box of the unknown area that are not free
/// (free: observed with p < `free_below`). At least 1.
template <class Space>
[[nodiscard]] double non_free_voxel_count(const Space& space, double free_below = 0.5) {
  detail::require_in_range("free_below", free_below, 0.0, 1.0);
  const KeyBox box = space.bounds_keys();
  std::uint64_t free_voxels = 0;
  space.for_each([&](const VoxelKey& k, const auto& s) {
    if (box.contains(k) && space.model().probability(s) < free_below) ++free_voxels;
  });
  const std::uint64_t total = box.volume();
  return total > free_voxels ? static_cast<double>(total - free_voxels) : 1.0;
}

}  // namespace nbs
