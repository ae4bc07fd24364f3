// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// The closed loop of Sec. 4.7: a first scan along one of the 13 initial paths (Sec. 4.7.2, chosen by a seed), then
/// plan → scan → integrate until the planner is done or n_abort scans were taken. `run_loop` drives any
/// `ScanDriver` (driver/concepts.hpp: real hardware, a replayed session, a simulation); `run_simulation` is
/// `run_loop` with a `SimulatedDriver` over a `ScanSimulator` (e.g. nbs::embree::SimulatedScanner, for a
/// LaserStripeProfiler or an AreaSensor): infinite robot workspace (Sec. 4.7), every planned path is executed as
/// planned. With a transfer planner (robot/transfer.hpp; issue 19 item 4) the loop also plans and records the arm's
/// joint-space transfer from the end of each scan to the start of the next; a failed transfer excludes its candidate
/// and the next best is tried (SimulationSetting::transfer_retries). With a robot the first scan's path is checked
/// for reach before anything runs.

#include <concepts>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "nbs/planner/planner_types.hpp"
#include "nbs/core/detail/random.hpp"
#include "nbs/driver/concepts.hpp"
#include "nbs/driver/simulated_driver.hpp"
#include "nbs/robot/reachability.hpp"
#include "nbs/robot/transfer.hpp"
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

/// A LoopPlanner whose robot the loop can move: `cp.space()` (the voxel space the transfers avoid),
/// `cp.robot_configuration()` (the robot's current joints, the end of the last scan; empty without an active robot),
/// `cp.reach(path)` (can the robot fly it now; always without a robot) and `p.reselect()` (the next best of the
/// last scored candidate set, the chosen one excluded: after a failed transfer). NbsPlanner and RuntimePlanner
/// model it.
template <class P>
concept RobotLoopPlanner = LoopPlanner<P> && requires(P& p, const P& cp, const LinearScanPath& path) {
  requires VoxelSpace<std::remove_cvref_t<decltype(cp.space())>>;
  { cp.robot_configuration() } -> std::convertible_to<JointVector>;
  { cp.reach(path) } -> std::same_as<ScanPathReach>;
  { p.reselect() } -> std::same_as<PlanResult>;
};

/// Settings of run_loop and run_simulation.
struct SimulationSetting {
  /// initial path (random_initial_scan_index(seed); with a robot the next one it can fly, reachable_initial_index);
  /// run_simulation: also the noise
  std::uint64_t seed = 1;
  int max_scans = 30;         ///< n_abort (Tab. 4.3): hard limit, ≥ 1
  std::optional<int> initial_index;  ///< force one of the 13 initial paths instead of the seeded choice
  /// With a transfer planner: after a failed transfer, up to this many further candidates (the next best reachable
  /// ones, PlanResult via reselect()) are tried before the loop stops with transfer_failed (≥ 0; 0: stop at once).
  int transfer_retries = 5;

  void validate() const {
    detail::require(max_scans >= 1, "SimulationSetting.max_scans must be >= 1, got ", max_scans);
    detail::require(transfer_retries >= 0, "SimulationSetting.transfer_retries must be >= 0, got ", transfer_retries);
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
  /// With a transfer planner, scans 2, 3, …: the arm's motion from the end of the previous scan to this scan's start
  /// (planned against the voxel space after the previous scan), executed before the scan. Empty otherwise.
  std::optional<TransferRecord> transfer;
};

/// Why the loop stopped.
/// `no_reachable_candidate`: with a robot, S had candidates but the robot could fly none (PlanStatus of that name).
/// `transfer_failed`: with a transfer planner, the arm found no motion to the chosen scan's start nor to any of the
/// next SimulationSetting::transfer_retries candidates (no scan taken; SimulationResult::failed_transfer says why).
enum class LoopStop : std::uint8_t { done, max_scans, no_candidates, transfer_failed, no_reachable_candidate };

[[nodiscard]] inline const char* to_string(LoopStop s) {
  switch (s) {
    case LoopStop::done: return "done";
    case LoopStop::max_scans: return "max_scans";
    case LoopStop::no_candidates: return "no_candidates";
    case LoopStop::transfer_failed: return "transfer_failed";
    case LoopStop::no_reachable_candidate: return "no_reachable_candidate";
  }
  return "?";
}

struct SimulationResult {
  std::vector<ScanRecord> records;
  LoopStop stop = LoopStop::max_scans;
  PlanStatus last_plan = PlanStatus::ok;  ///< status of the last next_best_scan (ok if never called)
  /// stop == transfer_failed: the last failed transfer (its failure, the time spent; failed_attempts: all tries of
  /// that step); no candidate of that step was scanned.
  std::optional<TransferRecord> failed_transfer;
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

/// The loop's stop reason for a plan that is not ok.
[[nodiscard]] inline LoopStop loop_stop(PlanStatus s) {
  if (s == PlanStatus::done) return LoopStop::done;
  return s == PlanStatus::no_reachable_candidate ? LoopStop::no_reachable_candidate : LoopStop::no_candidates;
}

namespace detail {
/// "initial path i of 13 (sensor from (x, y, z) m to (x, y, z) m, viewing direction (x, y, z)): <failure> at sample k"
[[nodiscard]] inline std::string describe_unreachable_initial(const LinearScanPath& path, int index,
                                                              const ScanPathReach& r) {
  const Vec3 a = path.start().position(), b = path.end_position(), z = path.start().pose().linear().col(2);
  std::ostringstream os;
  os.precision(17);
  os << "initial path " << index << " of " << kInitialScanPathCount << " (sensor from (" << a.x() << ", " << a.y()
     << ", " << a.z() << ") m to (" << b.x() << ", " << b.y() << ", " << b.z() << ") m, viewing direction ("
     << z.x() << ", " << z.y() << ", " << z.z() << ")): " << to_string(r.failure) << " at sample " << r.step;
  if (!r.link.empty()) os << " (link " << r.link << ")";
  return os.str();
}
}  // namespace detail

/// The index of the first scan's initial path for a planner whose robot must fly it (planner.reach: from the
/// robot's start configuration, links against the empty space): `forced` if given — InvalidArgument naming the
/// path's poses and the failure unless the robot can fly it —; else the seeded random_initial_scan_index(seed) or,
/// if the robot cannot fly that one, the next of the 13 in cyclic order (i + 1 mod 13, …) that it can fly;
/// InvalidArgument naming the seeded path if it can fly none. Without a robot: `forced` or the seeded index, as
/// run_loop always chose it. Nothing changed.
template <RobotLoopPlanner Planner>
[[nodiscard]] int reachable_initial_index(const Planner& planner, std::uint64_t seed, std::optional<int> forced) {
  const int seeded = forced.value_or(random_initial_scan_index(seed));
  const ScanPathReach r = planner.reach(planner.initial_scan(seeded));
  if (r.ok()) return seeded;
  const std::string what = detail::describe_unreachable_initial(planner.initial_scan(seeded), seeded, r);
  detail::require(!forced, "the robot cannot fly the first scan, ", what,
                  "; move the robot's base or the object, or choose another initial path");
  for (int k = 1; k < kInitialScanPathCount; ++k) {
    const int i = (seeded + k) % kInitialScanPathCount;
    if (planner.reach(planner.initial_scan(i)).ok()) return i;
  }
  detail::require(false, "the robot can fly none of the 13 initial scan paths; the seeded one: ", what,
                  "; move the robot's base or the object");
  return seeded;
}

/// Adds a reselect() step's counts to the step's statistics `st`; the chosen utility becomes the new one if
/// `chosen` (reselect() found a flyable candidate), else it stays.
inline void add_reselect_stats(IterationStats& st, const IterationStats& again, bool chosen = true) {
  st.unreachable += again.unreachable;
  for (std::size_t i = 0; i < st.unreachable_by_failure.size(); ++i)
    st.unreachable_by_failure[i] += again.unreachable_by_failure[i];
  st.reach_checks += again.reach_checks;
  st.t_reach_s += again.t_reach_s;
  st.t_nbs_s += again.t_nbs_s;
  if (chosen) st.best_utility = again.best_utility;
}

/// The transfer to the scan `plan` chose, `transfer_to(plan)` (nullopt: no transfer planner); if it fails, its
/// candidate stays excluded (it has left S) and up to `retries` next best candidates (planner.reselect()) are tried,
/// `plan` replaced by each (its stats add the reselect steps', also those of a last reselect() that found nothing
/// flyable). Returns the first transfer that succeeded, its failed_attempts the failures before it; else the last
/// failure, failed_attempts all of them (also when S ran out). The returned record's t_plan_s is the motion-planning
/// time of every try of this step (the failed ones included).
template <class Planner, class TransferTo>
[[nodiscard]] std::optional<TransferRecord> transfer_with_retries(Planner& planner, PlanResult& plan, int retries,
                                                                  TransferTo&& transfer_to) {
  int failures = 0;
  double t_failed_s = 0.0;  // motion planning of the failed tries before this one
  for (;;) {
    std::optional<TransferRecord> transfer = transfer_to(plan);
    if (!transfer) return transfer;
    transfer->t_plan_s += t_failed_s;
    if (transfer->ok()) {
      transfer->failed_attempts = failures;
      return transfer;
    }
    t_failed_s = transfer->t_plan_s;
    transfer->failed_attempts = ++failures;
    if constexpr (!RobotLoopPlanner<Planner>) {
      return transfer;
    } else {
      if (failures > retries) return transfer;
      PlanResult again = planner.reselect();
      IterationStats st = plan.stats;
      add_reselect_stats(st, again.stats, again.ok());
      if (!again.ok()) {
        plan.stats = st;
        return transfer;
      }
      plan = std::move(again);
      plan.stats = st;
    }
  }
}

namespace detail {
/// The loop of run_loop; `transfer_to(plan)` gives the transfer to the planned scan's start (nullopt: none).
template <class Planner, class Driver, class Callback, class TransferTo>
SimulationResult run_loop_with(Planner& planner, Driver& driver, const SimulationSetting& setting, Callback& on_scan,
                               TransferTo&& transfer_to) {
  SimulationResult out;
  double total = 0.0;
  using Sensor = std::remove_cvref_t<decltype(planner.sensor())>;
  const auto execute = [&](const LinearScanPath& planned, int index, std::optional<ScanCandidate> cand,
                           const IterationStats& plan, std::optional<TransferRecord> transfer) {
    const LinearScanPath path = detail::executed_scan_path<Sensor>(planned);
    ScanRecord rec;
    rec.scan = static_cast<int>(out.records.size()) + 1;
    rec.path = path;
    rec.candidate = std::move(cand);
    rec.initial_index = index;
    rec.transfer = std::move(transfer);
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
  int first = 0;
  if constexpr (RobotLoopPlanner<Planner>) first = reachable_initial_index(planner, setting.seed, setting.initial_index);
  else first = setting.initial_index.value_or(random_initial_scan_index(setting.seed));
  execute(planner.initial_scan(first), first, std::nullopt, {}, std::nullopt);
  while (static_cast<int>(out.records.size()) < setting.max_scans) {
    if (planner.done()) {
      out.stop = LoopStop::done;
      return out;
    }
    PlanResult plan = planner.next_best_scan();
    out.last_plan = plan.status;
    if (!plan.ok()) {
      out.stop = loop_stop(plan.status);
      return out;
    }
    std::optional<TransferRecord> transfer = transfer_with_retries(planner, plan, setting.transfer_retries, transfer_to);
    if (transfer && !transfer->ok()) {
      out.stop = LoopStop::transfer_failed;
      out.failed_transfer = std::move(transfer);
      return out;
    }
    const LinearScanPath path = plan.candidate->path;
    execute(path, -1, std::move(plan.candidate), plan.stats, std::move(transfer));
  }
  out.stop = planner.done() ? LoopStop::done : LoopStop::max_scans;
  return out;
}
}  // namespace detail

/// Runs the closed loop with `driver`: for every path (the initial one, then each planned one, as
/// detail::executed_scan_path gives it for the planner's sensor) `driver.move_to(path.start().pose())`, then
/// `driver.acquire(path)`, then `planner.integrate`. Stops when `planner.done()` (its termination criterion; for
/// c_a(30) of Sec. 4.7.2 give the planner MaxScansReached as termination), after `max_scans` scans, or when no
/// candidate is left. `on_scan(record)` is called after each scan is integrated (progress lines, ground-truth
/// metrics). Throws what the planner or the driver throw (InvalidArgument for an invalid setting); the planner then
/// holds the scans integrated before. A planner with a robot (RobotLoopPlanner): the first scan is one the robot
/// can fly (reachable_initial_index: the seeded one or the next reachable; InvalidArgument naming the pose before
/// any work if none, or if the forced SimulationSetting::initial_index is not).
template <LoopPlanner Planner, ScanDriver Driver, class Callback = NoScanCallback>
  requires std::invocable<Callback&, const ScanRecord&>
SimulationResult run_loop(Planner& planner, Driver& driver, const SimulationSetting& setting = {},
                          Callback&& on_scan = {}) {
  setting.validate();
  return detail::run_loop_with(planner, driver, setting, on_scan,
                               [](const PlanResult&) { return std::optional<TransferRecord>{}; });
}

/// The transfer to the scan `plan` chose (issue 19, item 4): from the robot's current joints (the end of the last
/// scan, planner.robot_configuration()) to the first configuration of the chosen path's joint trajectory
/// (PlanResult::joints; the current joints if it is empty), planned by `transfer` against planner.space() as it is
/// after the last scan (the space is read during the call, so the obstacles are always current). Timed.
template <RobotLoopPlanner Planner, class Transfer>
  requires TransferPlanner<Transfer, std::remove_cvref_t<decltype(std::declval<const Planner&>().space())>>
[[nodiscard]] TransferRecord plan_scan_transfer(const Planner& planner, const Transfer& transfer,
                                                const PlanResult& plan) {
  const JointVector from = planner.robot_configuration();
  const JointVector to = plan.joints.empty() ? from : plan.joints.front();
  return timed_transfer(transfer, from, to, planner.space());
}

/// run_loop that also moves the robot between scans: after each planned scan is chosen, the transfer to its start
/// (plan_scan_transfer: `transfer` from the end joints of the previous scan to the start joints of the next, against
/// the voxel space after the previous scan) is planned and recorded in ScanRecord::transfer before the scan is
/// taken. A failed transfer excludes its candidate (it has left the planner's candidate set) and the next best
/// reachable one is tried (planner.reselect()), up to setting.transfer_retries more (TransferRecord::failed_attempts
/// counts the failures); when all fail the loop stops with LoopStop::transfer_failed
/// (SimulationResult::failed_transfer) and none is scanned. The first scan (one of the 13 initial paths) has no
/// transfer. Throws InvalidArgument before any work unless transfer.joint_count() is 0 or the planner's robot's joint
/// count (0: the planner has no active robot), and what run_loop throws.
template <RobotLoopPlanner Planner, ScanDriver Driver, class Transfer, class Callback = NoScanCallback>
  requires TransferPlanner<Transfer, std::remove_cvref_t<decltype(std::declval<const Planner&>().space())>> &&
           std::invocable<Callback&, const ScanRecord&>
SimulationResult run_loop(Planner& planner, Driver& driver, const Transfer& transfer,
                          const SimulationSetting& setting = {}, Callback&& on_scan = {}) {
  setting.validate();
  const std::size_t n = transfer.joint_count();
  const auto m = static_cast<std::size_t>(planner.robot_configuration().size());
  detail::require(n == 0 || n == m, "run_loop: the transfer planner has ", n,
                  " joints but the planner's robot has ", m, " (0: no active robot)");
  return detail::run_loop_with(planner, driver, setting, on_scan, [&](const PlanResult& plan) {
    return std::optional<TransferRecord>(plan_scan_transfer(planner, transfer, plan));
  });
}

namespace detail {
/// The driver of run_simulation: `SimulatedDriver(scanner, planner.sensor(), seed)`.
template <class Planner, class Scanner>
[[nodiscard]] auto simulated_driver(const Planner& planner, const Scanner& scanner, std::uint64_t seed) {
  using Sensor = std::remove_cvref_t<decltype(planner.sensor())>;
  return SimulatedDriver<Scanner, Sensor>(scanner, planner.sensor(), seed);
}
}  // namespace detail

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
  auto driver = detail::simulated_driver(planner, scanner, setting.seed);
  return run_loop(planner, driver, setting, std::forward<Callback>(on_scan));
}

/// run_simulation with the robot's transfers between scans (run_loop with `transfer`).
template <RobotLoopPlanner Planner, class Scanner, class Transfer, class Callback = NoScanCallback>
  requires ScanSimulator<Scanner, std::remove_cvref_t<decltype(std::declval<const Planner&>().sensor())>> &&
           TransferPlanner<Transfer, std::remove_cvref_t<decltype(std::declval<const Planner&>().space())>> &&
           std::invocable<Callback&, const ScanRecord&>
SimulationResult run_simulation(Planner& planner, const Scanner& scanner, const Transfer& transfer,
                                const SimulationSetting& setting = {}, Callback&& on_scan = {}) {
  setting.validate();
  auto driver = detail::simulated_driver(planner, scanner, setting.seed);
  return run_loop(planner, driver, transfer, setting, std::forward<Callback>(on_scan));
}
}  // namespace nbs
