// The VoxelSpace concept (nbs/space/concepts.hpp): its conformance suite on every space model in the core and on a
// space written by a user in a few lines (the OctoMap space runs the same suite in tests/octomap).
#include <catch2/catch.hpp>

#include <unordered_map>

#include "nbs/space/hashed_block_backend.hpp"
#include "nbs/space/log_odds_model.hpp"
#include "nbs/space/probabilistic_voxel_space.hpp"
#include "nbs/space/ray_cast.hpp"
#include "nbs/space/ray_traversal.hpp"
#include "nbs/space/unknown_area_grid.hpp"
#include "support/voxel_space_conformance.hpp"

namespace {

// A user's voxel space: log-odds per key in a hash map (0 = unknown), +0.85 per hit, −0.4 per pass-through voxel.
// UnknownAreaGrid gives the geometry, walk_ray_generic the planning casts; `model()` is the space itself.
class UserSpace : public nbs::UnknownAreaGrid {
public:
  using State = float;
  UserSpace(double resolution_m, const nbs::Aabb& unknown_area) : UnknownAreaGrid(resolution_m, unknown_area) {}
  nbs::IntegrationStats integrate(const nbs::Scan& scan) {
    scan.validate();
    nbs::IntegrationStats st;
    st.points = scan.size();
    for (std::size_t i = 0; i < scan.size(); ++i)
      nbs::traverse_segment(grid(), scan.origin(i), scan.points[i], [&](const nbs::VoxelKey& k) {
        if (!bounds_keys().contains(k)) return;
        map_[k] += grid().in_voxel(scan.points[i], k) ? 0.85f : -0.4f;
        ++st.voxel_updates;
      });
    return st;
  }
  [[nodiscard]] const UserSpace& model() const { return *this; }
  [[nodiscard]] double probability(State s) const { return 1.0 / (1.0 + std::exp(-static_cast<double>(s))); }
  [[nodiscard]] bool occupied(State s) const { return s > 0.0f; }
  [[nodiscard]] State state(const nbs::VoxelKey& k) const { return map_.contains(k) ? map_.at(k) : 0.0f; }
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

}  // namespace

static_assert(nbs::VoxelSpace<UserSpace>);
static_assert(!nbs::BatchRayCastingSpace<UserSpace>);
static_assert(!nbs::NoiseModelSpace<UserSpace>);
static_assert(nbs::BatchRayCastingSpace<nbs::ProbabilisticVoxelSpace<>>);
static_assert(nbs::NoiseModelSpace<nbs::ProbabilisticVoxelSpace<>>);
static_assert(nbs::BlockBackend<nbs::HashedBlockBackend<nbs::ThesisState>>);

TEMPLATE_TEST_CASE("VoxelSpace conformance", "[space][concept]", nbs::ProbabilisticVoxelSpace<>,
                   (nbs::ProbabilisticVoxelSpace<nbs::HashedBlockBackend<nbs::LogOddsState>, nbs::LogOddsModel>),
                   UserSpace) {
  nbs::test::check_voxel_space_conformance<TestType>();
}
