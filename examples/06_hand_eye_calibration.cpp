// SPDX-License-Identifier: BSD-3-Clause
// 06 — hand-eye calibration (Sec. 3.2.1, Eqs. 3.1–3.2) and why it matters for the model. The sensor sits on the
// robot's flange at T_FS (flange → sensor), which the CAD drawing of the mount gives only to a few millimetres and
// degrees. nbs::calibrate_hand_eye (nbs/registration/hand_eye.hpp) estimates it from ~10 robot poses T_WF_i and the
// pose T_ST_i of a fixed checkerboard measured by the sensor at each: T_WF_i · T_FS · T_ST_i = T_WT for all i.
// Your driver then uses the estimate both ways: T_WS = T_WF · T_FS for every scan (Eq. 3.1) and T_WF = T_WS · T_FS⁻¹
// for every planned pose (Eq. 3.2). Here a simulated cell hides the true T_FS; the same Next-Best-Scan run with the
// calibrated and with the CAD T_FS shows how far the model moves off the object with a 5 mm / 2° error.
// Usage: 06_hand_eye_calibration (exits 1 if the calibrated T_FS is off by more than 0.25° or 1.5 mm, or its model is
// not closer to the true sphere than the CAD one's)

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <numbers>
#include <utility>
#include <vector>

#include "nbs/driver/concepts.hpp"
#include "nbs/planner/nbs_planner.hpp"
#include "nbs/planner/simulation_loop.hpp"
#include "nbs/registration/hand_eye.hpp"
#include "nbs/sensor/counter_gaussian.hpp"
#include "nbs/sensor/presets.hpp"
#include "nbs/sim/sphere_on_pedestal.hpp"  // nbs::SphereOnPedestal: exact ray casts at a sphere

using nbs::Pose;
using nbs::Vec3;
constexpr double kDeg = std::numbers::pi / 180.0;

Pose pose_of(const Vec3& axis, double angle_rad, const Vec3& t) {
  Pose T = Pose::Identity();
  T.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  T.translation() = t;
  return T;
}

// ==== The cell. Only the simulation knows kTrueT_FS; your program knows the CAD value (and, after calibration, the
// estimate). The mount puts the sensor 15 cm in front of the flange, looking along the flange's z axis. ====
const Pose kCadT_FS = pose_of(Vec3::UnitZ(), 0.0, Vec3(0.0, 0.03, 0.15));
const Pose kTrueT_FS = kCadT_FS * pose_of(Vec3(1.0, -1.0, 0.5), 2.0 * kDeg, Vec3(0.003, -0.004, 0.0));  // 5 mm, 2°
const nbs::CounterGaussian kNoise(2026);

/// `T` with noise per component in its outer frame: rotation exp(σ_r n) · R, translation t + σ_t n.
Pose noisy(const Pose& T, double sigma_rad, double sigma_m, std::uint64_t stream) {
  const Vec3 nr(kNoise(stream, 0), kNoise(stream, 1), kNoise(stream, 2)), nt(kNoise(stream, 3), kNoise(stream, 4),
                                                                             kNoise(stream, 5));
  Pose out = T;
  out.linear() = pose_of(nr, sigma_rad * nr.norm(), Vec3::Zero()).linear() * T.linear();
  out.translation() += sigma_m * nt;
  return out;
}

// ==== Calibration data, as a calibration routine records it: 10 views of a checkerboard on the table from 35 cm,
// tilted by 0°–30° from 8 directions and rolled by up to ±60° about the viewing axis (rotations about several axes —
// turning only about one axis leaves T_FS undetermined, and calibrate_hand_eye refuses it). The robot is commanded
// with the CAD T_FS; it reports its flange pose with 0.1 mm / 0.02° error, the camera the board with 0.2 mm / 0.05°. ====
struct CalibrationData {
  std::vector<Pose> T_WF, T_ST;
};

CalibrationData record_calibration_poses(const Pose& T_WT) {
  CalibrationData d;
  for (int k = 0; k < 10; ++k) {
    const double tilt = (k < 8 ? 30.0 : 0.0) * kDeg, azimuth = 45.0 * kDeg * k, roll = (k % 3 - 1) * 60.0 * kDeg;
    const Vec3 view = -Vec3(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
    Pose T_WS = Pose::Identity();  // looking at the board's centre
    T_WS.linear().col(2) = view;
    T_WS.linear().col(0) = view.unitOrthogonal();
    T_WS.linear().col(1) = view.cross(T_WS.linear().col(0));
    T_WS.linear() = T_WS.linear() * Eigen::AngleAxisd(roll, Vec3::UnitZ()).toRotationMatrix();
    T_WS.translation() = T_WT.translation() - 0.35 * view;
    const Pose T_WF = nbs::flange_from_sensor(T_WS, kCadT_FS);           // Eq. 3.2 with what we believe
    const Pose actual_T_WS = nbs::sensor_from_flange(T_WF, kTrueT_FS);   // Eq. 3.1 with what is
    const auto stream = static_cast<std::uint64_t>(2 * k);
    d.T_WF.push_back(noisy(T_WF, 0.02 * kDeg, 0.1e-3, stream));
    d.T_ST.push_back(noisy(actual_T_WS.inverse(Eigen::Isometry) * T_WT, 0.05 * kDeg, 0.2e-3, stream + 1));
  }
  return d;
}

// ==== A flange robot with a stripe sensor as an nbs::ScanDriver (as in examples/04): nbs sees sensor poses, the robot
// flange poses, converted with the hand-eye transform the program believes (`T_FS`). The physics use the true one: the
// beams leave from T_WF · kTrueT_FS, while the points are reported with T_WF · T_FS — a wrong T_FS bends the model. ====
class FlangeRobot {
public:
  FlangeRobot(const Pose& T_FS, nbs::LaserStripeProfiler sensor) : T_FS_(T_FS), sensor_(std::move(sensor)) {}

  void move_to(const Pose& T_WS) {
    nbs::validate_pose(T_WS, "FlangeRobot::move_to: target pose");
    T_WF_ = nbs::flange_from_sensor(T_WS, T_FS_);
  }
  [[nodiscard]] Pose current_pose() const { return nbs::sensor_from_flange(T_WF_, T_FS_); }

  [[nodiscard]] nbs::Scan acquire(const nbs::LinearScanPath& path) {
    const nbs::CounterGaussian range_noise(scans_++);
    nbs::Scan scan;
    for (const Pose& planned : sensor_.profile_poses(path)) {
      move_to(planned);
      const Pose actual = nbs::sensor_from_flange(T_WF_, kTrueT_FS);
      const auto k = static_cast<std::uint32_t>(scan.profile_poses.size());
      scan.profile_poses.push_back(current_pose());
      for (int i = 0; i < sensor_.points_per_profile; ++i, ++scan.rays_cast) {
        bool on_sphere = false;
        const Vec3 ray_S = sensor_.ray_direction_sensor(i);
        const auto t = sphere_.hit(actual.translation(), actual.linear() * ray_S, on_sphere);
        if (!t || !on_sphere || !sensor_.range.contains(*t)) continue;
        const double range = *t + sensor_.noise.sigma_m(*t) * range_noise(k, static_cast<std::uint64_t>(i));
        scan.add_point(current_pose() * (range * ray_S), k);  // the sensor's point, placed with the believed T_FS
      }
    }
    return scan;
  }

  nbs::SphereOnPedestal sphere_;  // the object: radius 4 cm, standing on the pedestal

private:
  Pose T_FS_, T_WF_ = Pose::Identity();
  nbs::LaserStripeProfiler sensor_;
  std::uint64_t scans_ = 0;
};
static_assert(nbs::ScanDriver<FlangeRobot>);

/// Models the sphere with the planner, the robot converting poses with `T_FS`; returns the RMS distance of the mesh
/// vertices to the true sphere (m).
double model_rms_distance(const Pose& T_FS, const char* label) {
  nbs::Parameters params;
  nbs::LaserStripeProfiler sensor = nbs::presets::dlr_lsp();
  sensor.points_per_profile = 200;   // fewer rays and 2 mm between profiles: the example runs in seconds
  sensor.profile_spacing_m = 0.002;
  nbs::NbsPlanner<> planner(params, sensor, nbs::SphereOnPedestal{}.unknown_area());
  FlangeRobot robot(T_FS, sensor);
  nbs::SimulationSetting loop;
  loop.max_scans = 8;
  const nbs::SimulationResult run = nbs::run_loop(planner, robot, loop);
  double sum = 0.0;
  const std::size_t n = planner.mesh().vertex_count();
  for (nbs::VertexId v = 0; v < n; ++v) {
    const double d = (planner.mesh().position(v) - robot.sphere_.center).norm() - robot.sphere_.radius_m;
    sum += d * d;
  }
  const double rms = n > 0 ? std::sqrt(sum / static_cast<double>(n)) : 1.0;
  std::printf("%-22s %zu scans, %6zu vertices, c_m %.3f, RMS distance to the true sphere %.3f mm\n", label,
              run.records.size(), n, planner.estimated_coverage(), 1e3 * rms);
  return rms;
}

int main() {
  try {
    // ---- Calibrate: what you copy (with your robot's flange poses and your camera's board poses). ---------------
    const Pose T_WT = pose_of(Vec3::UnitZ(), 0.3, Vec3(0.5, 0.0, 0.0));  // the board, unknown to the solver
    const CalibrationData data = record_calibration_poses(T_WT);
    nbs::HandEyeSetting setting;  // the noise of your measurements weights the refinement
    setting.target_rotation_sigma_rad = 0.05 * kDeg, setting.target_translation_sigma_m = 0.2e-3;
    setting.flange_rotation_sigma_rad = 0.02 * kDeg, setting.flange_translation_sigma_m = 0.1e-3;
    const nbs::HandEyeResult cal = nbs::calibrate_hand_eye(data.T_WF, data.T_ST, setting);
    // ---- End of the calibration. ----------------------------------------------------------------------------------

    const auto error = [](const Pose& T_FS) {
      return std::pair{Eigen::AngleAxisd(T_FS.linear() * kTrueT_FS.linear().transpose()).angle() / kDeg,
                       1e3 * (T_FS.translation() - kTrueT_FS.translation()).norm()};
    };
    const auto [cad_deg, cad_mm] = error(kCadT_FS);
    const auto [cf_deg, cf_mm] = error(cal.T_FS_closed_form);
    const auto [deg, mm] = error(cal.T_FS);
    std::printf("T_FS error: CAD %.3f deg %.2f mm; closed form %.3f deg %.2f mm; refined (%d iterations) %.3f deg "
                "%.2f mm\nresidual RMS %.3f deg %.3f mm (closed form %.3f deg %.3f mm), cost per pose %.2f\n",
                cad_deg, cad_mm, cf_deg, cf_mm, cal.iterations, deg, mm, cal.refined.rms_rotation_rad / kDeg,
                1e3 * cal.refined.rms_translation_m, cal.closed_form.rms_rotation_rad / kDeg,
                1e3 * cal.closed_form.rms_translation_m, cal.refined.cost_per_pose);

    // ---- Model the sphere with each T_FS: the robot's real mount is kTrueT_FS every time. -----------------------
    const double rms_true = model_rms_distance(kTrueT_FS, "true T_FS (reference):");
    const double rms_cal = model_rms_distance(cal.T_FS, "calibrated T_FS:");
    const double rms_cad = model_rms_distance(kCadT_FS, "CAD T_FS:");
    const bool ok = deg <= 0.25 && mm <= 1.5 && rms_cal < rms_cad;
    std::printf("calibrated T_FS within 0.25 deg / 1.5 mm and its model closer than the CAD one's "
                "(%.3f vs %.3f mm; exact T_FS %.3f mm): %s\n",
                1e3 * rms_cal, 1e3 * rms_cad, 1e3 * rms_true, ok ? "ok" : "FAILED");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "06_hand_eye_calibration: %s\n", e.what());
    return 1;
  }
}
