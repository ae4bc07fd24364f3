// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The closed loop of Sec. 4.7: a first scan along one of the 13 initial paths (Sec. 4.7.2, chosen by a seed), then
/// plan → scan → integrate until the planner is done or n_abort scans were taken. `run_loop` drives any
/// `ScanDriver` (driver/concepts.hpp: real hardware, a replayed session, a simulation); `run_simulation` is
/// `run_loop` with a `SimulatedDriver` over a `ScanSimulator` (e.g. nbs::embree::SimulatedScanner, for a
/// LaserStripeProfiler or an AreaSensor): infinite robot workspace (Sec. 4.7), every planned path is executed as
/// planned.

#include <concepts>
#include <cstdint>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include "nbs/planner/planner_types.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs/driver/concepts.hpp"
#include "nbs/driver/simulated_driver.hpp"
#include "nbs/sensor/area_sensor.hpp"

namespace nbs {

/// What the loop needs of a planner (NbsPlanner and RuntimePlanner model it).
template <class P>
concept LoopPlanner = requires(P& p, const P& cp, const Scan& scan, std::uint64_t seed) {
  { p.integrate(scan) } -> std::same_as<IntegrationReport>;
  { p.next_best_scan() } -> std::same_as<PlanResult>;
  { cp.done() } -> std::convertible_to<bool>;
  { cp.initial_scan(0) } -> std::same_as<LinearScanPath>;
  cp.sensor();
};

/// Settings of run_loop and run_simulation.
struct SimulationSetting {
  std::uint64_t seed = 1;     ///< initial path (random_initial_scan_index(seed)); run_simulation: also the noise
  int max_scans = 30;         ///< n_abort (Tab. 4.3): hard limit, ≥ 1
  std::optional<int> initial_index;  ///< force one of the 13 initial paths instead of the seeded choice

  void validate() const {
    detail::require(max_scans >= 1, "SimulationSetting.max_scans must be >= 1, got ", max_scans);
    detail::require(!initial_index || (*initial_index >= 0 && *initial_index < kInitialScanPathCount),
                    "SimulationSetting.initial_index must be in [0, 13), got ", initial_index.value_or(-1));
  }
};

/// One executed scan of the loop.
struct ScanRecord {
  int scan = 0;                       ///< 1-based scan number n_s
  /// Executed scan path: the planned (or initial) path; for an AreaSensor the single viewpoint at its start.
  LinearScanPath path;
  std::optional<ScanCandidate> candidate;  ///< the planned candidate (empty for the first scan)
  int initial_index = -1;             ///< index of the initial path (first scan only), else −1
  std::size_t points = 0;             ///< points measured
  IntegrationReport integration{};    ///< ĉ_m, d̄_m, mode after this scan, ...
  IterationStats planning{};          ///< the planning step that chose this scan (zero for the first scan)
  double path_length_m = 0.0;         ///< |s_p² − s_p¹| of this scan
  double total_path_length_m = 0.0;   ///< l_s so far (Sec. 4.7.2)
};

/// Why the loop stopped.
enum class LoopStop : std::uint8_t { done, max_scans, no_candidates };

struct SimulationResult {
  std::vector<ScanRecord> records;
  LoopStop stop = LoopStop::max_scans;
  PlanStatus last_plan = PlanStatus::ok;  ///< status of the last next_best_scan (ok if never called)
};

/// Callback that does nothing.
struct NoScanCallback {
  void operator()(const ScanRecord&) const {}
};

namespace detail {
/// The path the loop executes for a planned `path`: as planned for a line sensor; one frame at `path.start()` for an
/// AreaSensor (the 13 initial paths have length, the planner's area-sensor candidates do not).
template <class Sensor>
[[nodiscard]] LinearScanPath executed_scan_path(const LinearScanPath& path) {
  if constexpr (std::same_as<Sensor, AreaSensor>) {
    return LinearScanPath(path.start());
  } else {
    return path;
  }
}
}  // namespace detail

/// Runs the closed loop with `driver`: for every path (the initial one, then each planned one, as
/// detail::executed_scan_path gives it for the planner's sensor) `driver.move_to(path.start().pose())`, then
/// `driver.acquire(path)`, then `planner.integrate`. Stops when `planner.done()` (its termination criterion; for
/// c_a(30) of Sec. 4.7.2 give the planner MaxScansReached as termination), after `max_scans` scans, or when no
/// candidate is left. `on_scan(record)` is called after each scan is integrated (progress lines, ground-truth
/// metrics). Throws what the planner or the driver throw (InvalidArgument for an invalid setting); the planner then
/// holds the scans integrated before.
template <LoopPlanner Planner, ScanDriver Driver, class Callback = NoScanCallback>
  requires std::invocable<Callback&, const ScanRecord&>
SimulationResult run_loop(Planner& planner, Driver& driver, const SimulationSetting& setting = {},
                          Callback&& on_scan = {}) {
  setting.validate();
  SimulationResult out;
  double total = 0.0;
  using Sensor = std::remove_cvref_t<decltype(planner.sensor())>;
  const auto execute = [&](const LinearScanPath& planned, int index, std::optional<ScanCandidate> cand,
                           const IterationStats& plan) {
    const LinearScanPath path = detail::executed_scan_path<Sensor>(planned);
    ScanRecord rec;
    rec.scan = static_cast<int>(out.records.size()) + 1;
    rec.path = path;
    rec.candidate = std::move(cand);
    rec.initial_index = index;
    driver.move_to(path.start().pose());
    const Scan scan = driver.acquire(path);
    rec.points = scan.size();
    rec.integration = planner.integrate(scan);
    rec.planning = plan;
    rec.path_length_m = path.length();
    total += rec.path_length_m;
    rec.total_path_length_m = total;
    out.records.push_back(std::move(rec));
    on_scan(out.records.back());
  };
  const int first = setting.initial_index.value_or(random_initial_scan_index(setting.seed));
  execute(planner.initial_scan(first), first, std::nullopt, {});
  while (static_cast<int>(out.records.size()) < setting.max_scans) {
    if (planner.done()) {
      out.stop = LoopStop::done;
      return out;
    }
    PlanResult plan = planner.next_best_scan();
    out.last_plan = plan.status;
    if (!plan.ok()) {
      out.stop = plan.status == PlanStatus::done ? LoopStop::done : LoopStop::no_candidates;
      return out;
    }
    const LinearScanPath path = plan.candidate->path;
    execute(path, -1, std::move(plan.candidate), plan.stats);
  }
  out.stop = planner.done() ? LoopStop::done : LoopStop::max_scans;
  return out;
}

/// run_loop with `SimulatedDriver(scanner, planner.sensor(), setting.seed)`: scan i (0-based) uses sensor noise seed
/// splitmix64(seed ^ (0x5CA9 + i)). With an AreaSensor each scan is one frame at the start of the planned path
/// (`ScanRecord::path` is that single viewpoint, so l_s stays 0). Throws what the planner or the scanner throw
/// (InvalidArgument for an invalid setting).
template <LoopPlanner Planner, class Scanner, class Callback = NoScanCallback>
  requires ScanSimulator<Scanner, std::remove_cvref_t<decltype(std::declval<const Planner&>().sensor())>> &&
           std::invocable<Callback&, const ScanRecord&>
SimulationResult run_simulation(Planner& planner, const Scanner& scanner, const SimulationSetting& setting = {},
                                Callback&& on_scan = {}) {
  setting.validate();
  using Sensor = std::remove_cvref_t<decltype(planner.sensor())>;
  SimulatedDriver<Scanner, Sensor> driver(scanner, planner.sensor(), setting.seed);
  return run_loop(planner, driver, setting, std::forward<Callback>(on_scan));
}
}  // namespace nbs
