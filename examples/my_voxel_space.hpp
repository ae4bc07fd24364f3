// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The voxel space of example 05 (and of the VoxelSpace conformance test): a user's own VoxelSpace in a few lines.
// Log-odds per key in a hash map (0 = unknown), +0.85 per hit, −0.4 per voxel a beam passes (each beam updates its
// voxels, no per-scan "once" rule). UnknownAreaGrid gives the geometry (grid, bounds, voxel_bounds, bounds_keys),
// walk_ray_generic the planning casts; `model()` is the space itself.

#include <cmath>
#include <unordered_map>

#include "nbs/space/concepts.hpp"
#include "nbs/space/ray_cast.hpp"
#include "nbs/space/ray_traversal.hpp"
#include "nbs/space/unknown_area_grid.hpp"

class MyVoxelSpace : public nbs::UnknownAreaGrid {
public:
  using State = float;  // log-odds; State{} = 0 = p 0.5 = unknown
  MyVoxelSpace(double resolution_m, const nbs::Aabb& unknown_area) : UnknownAreaGrid(resolution_m, unknown_area) {}

  nbs::IntegrationStats integrate(const nbs::Scan& scan) {
    scan.validate();  // throws InvalidArgument before anything changes
    nbs::IntegrationStats st;
    st.points = scan.size();
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (!bounds().contains(scan.points[i])) continue;
      nbs::traverse_segment(grid(), scan.origin(i), scan.points[i], [&](const nbs::VoxelKey& k) {
        if (!bounds_keys().contains(k)) return;
        map_[k] += grid().in_voxel(scan.points[i], k) ? 0.85f : -0.4f;
        ++st.voxel_updates;
      });
    }
    return st;
  }
  // How a state reads (model() may be the space itself).
  [[nodiscard]] const MyVoxelSpace& model() const { return *this; }
  [[nodiscard]] double probability(State s) const { return 1.0 / (1.0 + std::exp(-static_cast<double>(s))); }
  [[nodiscard]] bool occupied(State s) const { return s > 0.0f; }
  // Queries per key and per world point.
  [[nodiscard]] State state(const nbs::VoxelKey& k) const {
    const auto it = map_.find(k);
    return it == map_.end() ? State{} : it->second;
  }
  [[nodiscard]] double probability(const nbs::VoxelKey& k) const { return probability(state(k)); }
  [[nodiscard]] double probability(const nbs::Vec3& x) const {
    const auto k = grid().key_of(x);
    return k ? probability(*k) : 0.5;
  }
  [[nodiscard]] bool occupied(const nbs::VoxelKey& k) const { return occupied(state(k)); }
  [[nodiscard]] bool observed(const nbs::VoxelKey& k) const { return map_.contains(k); }
  template <class F>
  void for_each(F&& f) const {
    for (const auto& [k, s] : map_) f(k, s);
  }
  template <class Visit>
  nbs::RaycastResult cast_ray(const nbs::Ray& ray, Visit&& visit) const {
    return nbs::walk_ray_generic(*this, ray, visit);
  }

private:
  std::unordered_map<nbs::VoxelKey, float, nbs::VoxelKeyHash> map_;
};
static_assert(nbs::VoxelSpace<MyVoxelSpace>);  // fails here, naming what is missing, if the contract is not met
