// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The compiled runtime facade for CLIs and configuration files: a closed set of methods (thesis Fig. 4.19 codes,
/// Sec. 4.7) and `RuntimePlanner`, a std::variant over the three precompiled NbsPlanner search spaces whose utility
/// is chosen at run time (SelectionUtility, one switch over precompiled terms). No string-keyed registration.
///
/// | code | selection × search |
/// |---|---|
/// | R_S, R_B, R_H | Random × Sphere / Boundary Search / Boundary Search + Hole Rescan |
/// | I_S, I_B, I_H | IG (ω = 0) × ... |
/// | Q_S, Q_B, Q_H | Quality (ω = 1) × ... |
/// | C_S, C_B, C_H | IG/Quality (ω(n_s), Eq. 4.31) × ... |
/// | OA_H, UV_H, RSV_H, RSE_H, PC_H, AE_H, VG_H | peer metrics (Delmerico et al. 2018; VG: Vasquez-Gomez) × BS+HR |
/// | SEE | the peer planner Surface Edge Explorer (Border & Gammell): its density frontier (SurfaceEdgeExplorer) and its nearest-view selection (NearestViewUtility) |

#include <array>
#include <cctype>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "nbs/planner/nbs_planner.hpp"
#include "nbs/robot/any_robot.hpp"
#include "nbs/registration/selectable_registration.hpp"

namespace nbs {

/// Search space of Sec. 4.7 (second letter of a method code), and SEE's frontier (the whole code SEE).
enum class SearchSpace : std::uint8_t { sphere, boundary, boundary_hole, surface_edge };

/// `S`, `B`, `H` or `SEE`.
[[nodiscard]] constexpr std::string_view format_search(SearchSpace s) {
  switch (s) {
    case SearchSpace::sphere: return "S";
    case SearchSpace::boundary: return "B";
    case SearchSpace::boundary_hole: return "H";
    case SearchSpace::surface_edge: return "SEE";
  }
  return "?";
}

/// A planning method: selection criterion × search space; the default is nbs's SGU_H. SEE (search surface_edge)
/// selects by its own rule (NearestViewUtility); its `selection` is unused and stays at the default.
struct Method {
  Selection selection = Selection::surface_gain_unseen;
  SearchSpace search = SearchSpace::boundary_hole;
  friend constexpr bool operator==(const Method&, const Method&) = default;
};

/// The SEE peer planner (selection: Method's default, unused).
inline constexpr Method kSeeMethod{Method{}.selection, SearchSpace::surface_edge};

/// nbs's default method SGU_H (issue 18: Method{}) and the thesis's best, C_H (Tab. 4.5).
inline constexpr Method kDefaultMethod{};
inline constexpr Method kThesisMethod{Selection::ig_quality, SearchSpace::boundary_hole};

/// The 12 thesis methods (R, I, Q, C × S, B, H), the 7 peer metrics and surface gain SG, SGU (ours) with BS+HR, then
/// the peer planner SEE.
inline constexpr std::array<Method, 22> kAllMethods = [] {
  std::array<Method, 22> m{};
  std::size_t i = 0;
  for (Selection s : {Selection::random, Selection::information_gain, Selection::quality, Selection::ig_quality})
    for (SearchSpace g : {SearchSpace::sphere, SearchSpace::boundary, SearchSpace::boundary_hole}) m[i++] = {s, g};
  for (Selection s : {Selection::occlusion_aware, Selection::unobserved_voxel, Selection::rear_side_voxel,
                      Selection::rear_side_entropy, Selection::proximity_count, Selection::average_entropy,
                      Selection::vasquez_gomez, Selection::surface_gain, Selection::surface_gain_unseen})
    m[i++] = {s, SearchSpace::boundary_hole};
  m[i++] = kSeeMethod;
  return m;
}();

/// The method code, e.g. "C_H" (Fig. 4.19), "OA_H" or "SEE".
[[nodiscard]] inline std::string format_method(const Method& m) {
  if (m.search == SearchSpace::surface_edge) return std::string(format_search(m.search));
  return std::string(format_selection(m.selection)) + "_" + std::string(format_search(m.search));
}

/// Parses a method code (case-insensitive, surrounding blanks ignored): one of kAllMethods. Throws InvalidArgument
/// naming the input and listing every valid code otherwise.
[[nodiscard]] inline Method parse_method(std::string_view code) {
  while (!code.empty() && std::isspace(static_cast<unsigned char>(code.front()))) code.remove_prefix(1);
  while (!code.empty() && std::isspace(static_cast<unsigned char>(code.back()))) code.remove_suffix(1);
  std::string upper(code);
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  std::string valid;
  for (const Method& m : kAllMethods) {
    const std::string f = format_method(m);
    if (upper == f) return m;
    valid += valid.empty() ? "" : ", ";
    valid += f;
  }
  throw InvalidArgument(detail::concat("unknown planning method '", code, "'; valid codes: ", valid));
}

/// The planner types behind the facade (each instantiated once, here).
template <SearchSpace S>
using RuntimeSearch = std::conditional_t<
    S == SearchSpace::sphere, SphereSpace,
    std::conditional_t<S == SearchSpace::boundary, BoundarySpace,
                       std::conditional_t<S == SearchSpace::surface_edge, SurfaceEdgeSpace, BoundaryHoleSpace>>>;
/// SEE's own selection for its search, the run-time selection otherwise.
template <SearchSpace S>
using RuntimeUtility = std::conditional_t<S == SearchSpace::surface_edge, NearestViewUtility, SelectionUtility>;
template <SearchSpace S>
using RuntimePlannerOf = NbsPlanner<RuntimeUtility<S>, RuntimeSearch<S>, LaserStripeProfiler, NoCollisions,
                                    SelectableTermination, ProbabilisticVoxelSpace<>, StreamingMesh, SelectableCoverage,
                                    SelectableRegistration, RobotReach<AnyRobot>>;

/// The choices that are policy types in NbsPlanner but run-time values in the facade: the mesh's settings, the
/// form of ĉ_m and the stop rule. Default: NbsPlanner<>'s (NoiseRobustStreamingMesh, UnseenLoopCoverage with the
/// enclosure test, SettledTermination).
struct RuntimeModels {
  /// NoiseRobustStreamingMesh's settings (true): one layer of vertices under range noise instead of a slab, half
  /// the vertices, vertex RMS error 0.66 mm instead of 1.07 mm on the bunny, ≈ 2.6–2.9× the points per second.
  /// false: the thesis's stream as written (Sec. 3.3.1, StreamingMesh); pair it with coverage_estimate = thesis.
  bool noise_robust_mesh = true;
  /// The ĉ_m form (SelectableCoverage; the unseen forms are made for the noise-robust mesh, and with the thesis
  /// form the noise-robust mesh never reaches ĉ_m 0.8 on the bunny: one layer leaves few small loops).
  CoverageEstimate coverage_estimate = CoverageEstimate::unknown_open;
  /// The stop rule (SelectableTermination; its thresholds come from Parameters).
  StopRule stop_rule = StopRule::settled;
  /// The thesis's mesh, ĉ_m and stop rule (Secs. 3.3.1, 4.4, 4.6) together: the unseen forms are meaningless on the
  /// layered mesh.
  [[nodiscard]] static RuntimeModels thesis() {
    RuntimeModels m;
    m.noise_robust_mesh = false;
    m.coverage_estimate = CoverageEstimate::thesis;
    m.stop_rule = StopRule::thesis;
    return m;
  }
  /// The registration step before each scan is integrated (SelectableRegistration): none (exact poses) or the
  /// thesis's ICP (Sec. 3.2.3) with `icp`.
  RegistrationMethod registration = RegistrationMethod::none;
  IcpSetting icp{};
  /// The options of the selection criteria that are not thesis parameters (SGU's β, SG's l_0, ...).
  SelectionOptions selection{};
  /// The StreamingMesh settings of this choice over `box` (the pass-through box): StreamingMeshSettings::from, made
  /// noise-robust (NoiseRobustStreamingMesh::robust) if noise_robust_mesh. Throws InvalidArgument for bad params.
  [[nodiscard]] StreamingMeshSettings mesh_settings(const Parameters& params, const Aabb& box) const {
    const StreamingMeshSettings s = StreamingMeshSettings::from(params, box);
    return noise_robust_mesh ? NoiseRobustStreamingMesh::robust(s) : s;
  }
  bool operator==(const RuntimeModels&) const = default;
};

/// A planner whose method is chosen at run time. Same API and guarantees as NbsPlanner (LSP sensor, default space,
/// termination chosen by RuntimeModels::stop_rule,
/// mesh, termination, infinite workspace). Not copyable (owns the models); movable.
class RuntimePlanner {
public:
  using Variant = std::variant<RuntimePlannerOf<SearchSpace::sphere>, RuntimePlannerOf<SearchSpace::boundary>,
                               RuntimePlannerOf<SearchSpace::boundary_hole>, RuntimePlannerOf<SearchSpace::surface_edge>>;

  /// Throws InvalidArgument for invalid parameters, sensor, box or setting.
  RuntimePlanner(const Method& method, const Parameters& params, const LaserStripeProfiler& sensor,
                 const Aabb& unknown_area, const PlannerSetting& setting = {}, const RuntimeModels& models = {})
      : method_(method), models_(models), planner_(make(method, params, sensor, unknown_area, setting, models)) {}
  /// Same, from a method code ("C_H", ...).
  RuntimePlanner(std::string_view code, const Parameters& params, const LaserStripeProfiler& sensor,
                 const Aabb& unknown_area, const PlannerSetting& setting = {}, const RuntimeModels& models = {})
      : RuntimePlanner(parse_method(code), params, sensor, unknown_area, setting, models) {}

  [[nodiscard]] const Method& method() const { return method_; }
  [[nodiscard]] const RuntimeModels& models() const { return models_; }
  [[nodiscard]] std::string code() const { return format_method(method_); }

  IntegrationReport integrate(const Scan& scan) {
    return std::visit([&](auto& p) { return p.integrate(scan); }, planner_);
  }
  [[nodiscard]] PlanResult next_best_scan() {
    return std::visit([](auto& p) { return p.next_best_scan(); }, planner_);
  }
  /// NbsPlanner::reselect(): the next best of the last scored candidate set (after a failed transfer).
  [[nodiscard]] PlanResult reselect() {
    return std::visit([](auto& p) { return p.reselect(); }, planner_);
  }
  /// NbsPlanner::reach(path): can the robot fly `path` now (always without set_robot)?
  [[nodiscard]] ScanPathReach reach(const LinearScanPath& path) const {
    return std::visit([&](const auto& p) { return p.reach(path); }, planner_);
  }
  [[nodiscard]] bool done() const {
    return std::visit([](const auto& p) { return p.done(); }, planner_);
  }
  [[nodiscard]] LinearScanPath first_scan(std::uint64_t seed) const {
    return std::visit([&](const auto& p) { return p.first_scan(seed); }, planner_);
  }
  [[nodiscard]] LinearScanPath initial_scan(int index) const {
    return std::visit([&](const auto& p) { return p.initial_scan(index); }, planner_);
  }
  /// NbsPlanner::progress() of the planner held (coverage_history borrowed: valid until the next integrate()).
  [[nodiscard]] ModelProgress progress() const {
    return std::visit([](const auto& p) { return p.progress(); }, planner_);
  }
  [[nodiscard]] SearchMode mode() const {
    return std::visit([](const auto& p) { return p.mode(); }, planner_);
  }
  [[nodiscard]] const StreamingMesh& mesh() const {
    return std::visit([](const auto& p) -> const StreamingMesh& { return p.mesh(); }, planner_);
  }
  [[nodiscard]] const ProbabilisticVoxelSpace<>& space() const {
    return std::visit([](const auto& p) -> const ProbabilisticVoxelSpace<>& { return p.space(); }, planner_);
  }
  [[nodiscard]] const LaserStripeProfiler& sensor() const {
    return std::visit([](const auto& p) -> const LaserStripeProfiler& { return p.sensor(); }, planner_);
  }
  /// Plans for `robot` from now on, standing at `start` (RobotReach); without it the sensor flies freely. Throws
  /// InvalidArgument (nothing changed) for a bad start or setting.
  void set_robot(const AnyRobot& robot, const JointVector& start, const RobotReach<AnyRobot>::Setting& setting = {}) {
    RobotReach<AnyRobot> reach(robot, start, setting);
    std::visit([&](auto& p) { p.robot = reach; }, planner_);
  }
  /// The robot's current joints (RobotReach::configuration()); empty unless set_robot was called.
  [[nodiscard]] JointVector robot_configuration() const {
    return robot().active() ? robot().configuration() : JointVector{};
  }
  /// The robot policy (inactive unless set_robot was called): the robot's current configuration, its setting.
  [[nodiscard]] const RobotReach<AnyRobot>& robot() const {
    return std::visit([](const auto& p) -> const RobotReach<AnyRobot>& { return p.robot; }, planner_);
  }
  [[nodiscard]] const Aabb& unknown_area() const {
    return std::visit([](const auto& p) -> const Aabb& { return p.unknown_area(); }, planner_);
  }
  /// The underlying planner (e.g. std::get_if<RuntimePlannerOf<SearchSpace::boundary_hole>>).
  [[nodiscard]] Variant& variant() { return planner_; }
  [[nodiscard]] const Variant& variant() const { return planner_; }

private:
  template <SearchSpace S>
  static Variant build(Selection sel, const Parameters& params, const LaserStripeProfiler& sensor, const Aabb& box,
                       const PlannerSetting& setting, const RuntimeModels& models) {
    Variant v(std::in_place_type<RuntimePlannerOf<S>>, params, sensor, box, setting,
              models.mesh_settings(params, box));
    auto& p = std::get<RuntimePlannerOf<S>>(v);
    if constexpr (std::same_as<RuntimeUtility<S>, SelectionUtility>) {
      p.utility.setting.selection = sel;
      p.utility.setting.options = models.selection;
    }
    p.coverage.setting.form = models.coverage_estimate;
    p.termination.rule = models.stop_rule;
    p.registration = SelectableRegistration{models.registration, models.icp};
    return v;
  }
  static Variant make(const Method& m, const Parameters& params, const LaserStripeProfiler& sensor, const Aabb& box,
                      const PlannerSetting& setting, const RuntimeModels& models) {
    bool known = false;
    for (const Method& k : kAllMethods) known = known || k == m;
    detail::require(known, "RuntimePlanner: method ", format_method(m), " is not one of the precompiled methods");
    switch (m.search) {
      case SearchSpace::sphere: return build<SearchSpace::sphere>(m.selection, params, sensor, box, setting, models);
      case SearchSpace::boundary:
        return build<SearchSpace::boundary>(m.selection, params, sensor, box, setting, models);
      case SearchSpace::surface_edge:
        return build<SearchSpace::surface_edge>(m.selection, params, sensor, box, setting, models);
      case SearchSpace::boundary_hole: break;
    }
    return build<SearchSpace::boundary_hole>(m.selection, params, sensor, box, setting, models);
  }

  Method method_;
  RuntimeModels models_;
  Variant planner_;
};

}  // namespace nbs
