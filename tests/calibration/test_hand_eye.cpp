// SPDX-License-Identifier: BSD-3-Clause
// Hand-eye calibration (nbs/registration/hand_eye.hpp) against a known X: the target measurements are generated from
// the pose loop T_WF_i · X · T_ST_i = T_WT, exactly or with seeded noise on both the target and the flange poses.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "nbs/core/detail/random.hpp"
#include "nbs/driver/concepts.hpp"
#include "nbs/registration/hand_eye.hpp"
#include "nbs/sensor/counter_gaussian.hpp"
#include "nbs_catch.hpp"

namespace {
using nbs::Mat3;
using nbs::Pose;
using nbs::Vec3;

Pose pose_of(const Vec3& rotation_vector, const Vec3& t) {
  Pose T = Pose::Identity();
  T.linear() = nbs::detail::hand_eye::rotation_exp(rotation_vector);
  T.translation() = t;
  return T;
}

const Pose kX = pose_of(Vec3(0.3, -0.2, 1.2), Vec3(0.03, -0.05, 0.12));  // the hidden T_FS
const Pose kT_WT = pose_of(Vec3(0.0, 0.0, 0.4), Vec3(0.6, 0.1, 0.0));    // a target on the table

/// `T` with noise in its left (outer) frame: rotation exp(σ_r n) · R, translation t + σ_t n, n ~ N(0, I) per
/// component from (gauss, stream).
Pose noisy(const Pose& T, double sigma_rad, double sigma_m, const nbs::CounterGaussian& gauss, std::uint64_t stream) {
  const Vec3 nr(gauss(stream, 0), gauss(stream, 1), gauss(stream, 2));
  const Vec3 nt(gauss(stream, 3), gauss(stream, 4), gauss(stream, 5));
  Pose out = T;
  out.linear() = nbs::detail::hand_eye::rotation_exp(sigma_rad * nr) * T.linear();
  out.translation() += sigma_m * nt;
  return out;
}

struct Noise {
  double target_rad = 0.0, target_m = 0.0, flange_rad = 0.0, flange_m = 0.0;
};

struct Data {
  std::vector<Pose> flange, target;  // reported T_WF_i, measured T_ST_i
};

/// `n` sensor poses 0.3–0.5 m from the target, tilted 10°–45° from the vertical, any azimuth, rolled by up to
/// ±`max_roll_rad` about the viewing axis; the flange pose T_WF = T_WS · X⁻¹ and the target T_ST = T_WS⁻¹ · T_WT.
Data simulate(std::uint64_t seed, int n, const Noise& noise = {}, double max_roll_rad = 1.0) {
  std::mt19937_64 rng(seed);
  const auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * nbs::detail::uniform01(rng); };
  const nbs::CounterGaussian gauss(seed);
  Data d;
  for (int k = 0; k < n; ++k) {
    const double tilt = uniform(0.17, 0.79), azimuth = uniform(0.0, 2.0 * std::numbers::pi);
    const Vec3 view = -Vec3(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
    const double ax = uniform(-0.03, 0.03), ay = uniform(-0.03, 0.03);
    const Vec3 aim = kT_WT.translation() + Vec3(ax, ay, 0.0);
    Mat3 R;
    R.col(2) = view;
    R.col(0) = view.unitOrthogonal();
    R.col(1) = R.col(2).cross(R.col(0));
    R = R * Eigen::AngleAxisd(uniform(-max_roll_rad, max_roll_rad), Vec3::UnitZ()).toRotationMatrix();
    Pose T_WS = Pose::Identity();
    T_WS.linear() = R;
    T_WS.translation() = aim - uniform(0.3, 0.5) * view;
    const Pose T_WF = nbs::flange_from_sensor(T_WS, kX);  // Eq. 3.2
    const Pose T_ST = T_WS.inverse(Eigen::Isometry) * kT_WT;
    const auto s = static_cast<std::uint64_t>(2 * k);
    d.flange.push_back(noisy(T_WF, noise.flange_rad, noise.flange_m, gauss, s));
    d.target.push_back(noisy(T_ST, noise.target_rad, noise.target_m, gauss, s + 1));
  }
  return d;
}

double rotation_error_rad(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.linear() * b.linear().transpose()).angle();
}
double translation_error_m(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }

std::string message_of(const Data& d, const nbs::HandEyeSetting& setting = {}) {
  try {
    (void)nbs::calibrate_hand_eye(d.flange, d.target, setting);
  } catch (const nbs::InvalidArgument& e) {
    return e.what();
  }
  return "(no exception)";
}

constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

TEST_CASE("noiseless poses recover X and T_WT to 1e-9", "[calibration][hand_eye]") {
  for (std::uint64_t seed = 1; seed <= 5; ++seed)
    for (const double max_roll : {1.0, std::numbers::pi}) {  // π: some pairs turn by ≈ 180° and are left out of R_X
      const Data d = simulate(seed, 10, {}, max_roll);
      const nbs::HandEyeResult r = nbs::calibrate_hand_eye(d.flange, d.target);
      INFO("seed " << seed << ", max roll " << max_roll << " rad, pairs in R_X " << r.pairs);
      CHECK((r.T_FS_closed_form.matrix() - kX.matrix()).cwiseAbs().maxCoeff() < 1e-9);
      CHECK((r.T_FS.matrix() - kX.matrix()).cwiseAbs().maxCoeff() < 1e-9);
      CHECK((r.T_WT.matrix() - kT_WT.matrix()).cwiseAbs().maxCoeff() < 1e-9);
      CHECK(r.refined.rms_rotation_rad < 1e-9);
      CHECK(r.refined.rms_translation_m < 1e-9);
      CHECK(r.rotation_spread_rad > 0.1);
      // Eq. 3.1 with the estimate closes the loop: T_WS · T_ST = T_WT.
      CHECK((nbs::sensor_from_flange(d.flange[3], r.T_FS) * d.target[3]).matrix().isApprox(kT_WT.matrix(), 1e-9));
    }
}

TEST_CASE("three poses suffice; a pair turning by ≈ 180° is left out of R_X", "[calibration][hand_eye]") {
  Data d;  // pairs (0, 1) and (1, 2) turn by ≈ 90° about different axes, pair (0, 2) by 175°
  for (const Pose& T_WF : {pose_of(Vec3::Zero(), Vec3(0.5, 0.0, 0.4)),
                           pose_of(Vec3(std::numbers::pi / 2, 0.0, 0.0), Vec3(0.45, 0.05, 0.42)),
                           pose_of(175.0 * kDeg * Vec3(1.0, 0.3, 0.0).normalized(), Vec3(0.52, -0.04, 0.38))}) {
    d.flange.push_back(T_WF);
    d.target.push_back((T_WF * kX).inverse(Eigen::Isometry) * kT_WT);
  }
  const nbs::HandEyeResult r = nbs::calibrate_hand_eye(d.flange, d.target);
  CHECK(r.pairs == 2);
  CHECK((r.T_FS_closed_form.matrix() - kX.matrix()).cwiseAbs().maxCoeff() < 1e-9);
  CHECK((r.T_FS.matrix() - kX.matrix()).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("with noise the estimate is within tolerance and the refinement beats the closed form",
          "[calibration][hand_eye]") {
  // Target measured with 0.2 mm and 0.05° per component, flange reported with 0.1 mm and 0.02°; 12 poses.
  const Noise noise{0.05 * kDeg, 0.2e-3, 0.02 * kDeg, 0.1e-3};
  nbs::HandEyeSetting setting;
  setting.target_rotation_sigma_rad = 0.05 * kDeg;
  setting.target_translation_sigma_m = 0.2e-3;
  setting.flange_rotation_sigma_rad = 0.02 * kDeg;
  setting.flange_translation_sigma_m = 0.1e-3;
  constexpr int kSeeds = 20;
  double cf_rot = 0.0, cf_trans = 0.0, lm_rot = 0.0, lm_trans = 0.0, worst_rot = 0.0, worst_trans = 0.0;
  double chi2 = 0.0;
  int max_iterations = 0;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
    const Data d = simulate(seed, 12, noise);
    const nbs::HandEyeResult r = nbs::calibrate_hand_eye(d.flange, d.target, setting);
    INFO("seed " << seed);
    // The refinement only takes steps that lower its cost; with the true sigmas that cost is χ²-like, ≈ 6 − 12/N.
    CHECK(r.refined.cost_per_pose <= r.closed_form.cost_per_pose);
    CHECK(r.refined.cost_per_pose < 10.0);
    chi2 += r.refined.cost_per_pose / kSeeds;
    cf_rot += rotation_error_rad(r.T_FS_closed_form, kX) / kSeeds;
    cf_trans += translation_error_m(r.T_FS_closed_form, kX) / kSeeds;
    lm_rot += rotation_error_rad(r.T_FS, kX) / kSeeds;
    lm_trans += translation_error_m(r.T_FS, kX) / kSeeds;
    worst_rot = std::max(worst_rot, rotation_error_rad(r.T_FS, kX));
    worst_trans = std::max(worst_trans, translation_error_m(r.T_FS, kX));
    max_iterations = std::max(max_iterations, r.iterations);
  }
  std::printf("hand-eye, %d seeds x 12 poses: mean error of X closed form %.4f deg %.3f mm, refined %.4f deg %.3f mm; "
              "worst refined %.4f deg %.3f mm; at most %d iterations; mean cost per pose %.2f\n",
              kSeeds, cf_rot / kDeg, 1e3 * cf_trans, lm_rot / kDeg, 1e3 * lm_trans, worst_rot / kDeg,
              1e3 * worst_trans, max_iterations, chi2);
  // Tolerance for 12 poses at this noise, every seed: 0.25° and 1.5 mm (measured: worst 0.154°, 0.923 mm).
  CHECK(worst_rot < 0.25 * kDeg);
  CHECK(worst_trans < 1.5e-3);
  CHECK(lm_rot < cf_rot);
  CHECK(lm_trans < cf_trans);
}

TEST_CASE("max_iterations = 0 returns the closed form", "[calibration][hand_eye]") {
  const Data d = simulate(3, 6, {0.05 * kDeg, 0.2e-3, 0.0, 0.0});
  nbs::HandEyeSetting setting;
  setting.max_iterations = 0;
  const nbs::HandEyeResult r = nbs::calibrate_hand_eye(d.flange, d.target, setting);
  CHECK(r.iterations == 0);
  CHECK(r.T_FS.matrix() == r.T_FS_closed_form.matrix());
  CHECK(r.refined.rms_translation_m == r.closed_form.rms_translation_m);
}

TEST_CASE("rotations about one axis cannot determine X: refused, naming the axis", "[calibration][hand_eye]") {
  // The flange turns only about the world z axis (its own z axis): any shift of X along that axis fits.
  for (const double sigma : {0.0, 0.02 * kDeg}) {
    Data d;
    const nbs::CounterGaussian gauss(7);
    for (int k = 0; k < 8; ++k) {
      const Pose T_WF = pose_of(Vec3(0.0, 0.0, 0.4 * k - 1.2), Vec3(0.5 + 0.02 * k, -0.01 * k, 0.4));
      d.flange.push_back(noisy(T_WF, sigma, 0.0, gauss, static_cast<std::uint64_t>(k)));
      d.target.push_back((T_WF * kX).inverse(Eigen::Isometry) * kT_WT);
    }
    const std::string what = message_of(d);
    INFO(what);
    CHECK(what.find("about one axis, (0.000, 0.000, 1.000) in the flange frame") != std::string::npos);
    CHECK(what.find("min_rotation_spread_rad") != std::string::npos);
  }
  // Rotations of a few hundredths of a degree: too small.
  Data tiny;
  for (int k = 0; k < 5; ++k) {
    const Pose T_WF = pose_of(Vec3(1e-4 * k, -2e-4 * k, 1e-4), Vec3(0.5, 0.1 * k, 0.4));
    tiny.flange.push_back(T_WF);
    tiny.target.push_back((T_WF * kX).inverse(Eigen::Isometry) * kT_WT);
  }
  CHECK(message_of(tiny).find("too small") != std::string::npos);
}

TEST_CASE("bad input throws InvalidArgument naming the problem", "[calibration][hand_eye]") {
  const Data good = simulate(5, 6);
  Data d = good;
  d.target.pop_back();
  CHECK(message_of(d).find("flange_poses has 6 poses but target_poses has 5") != std::string::npos);
  d = good;
  d.flange.resize(2), d.target.resize(2);
  CHECK(message_of(d).find("at least 3 pose pairs, got 2") != std::string::npos);
  d = good;
  d.flange[4].translation().x() = std::numeric_limits<double>::quiet_NaN();
  CHECK(message_of(d).find("flange_poses[4] has a non-finite coefficient") != std::string::npos);
  d = good;
  d.target[1].linear() *= 1.01;
  CHECK(message_of(d).find("target_poses[1] rotation is not orthonormal") != std::string::npos);
  nbs::HandEyeSetting setting;
  setting.target_translation_sigma_m = 0.0;
  CHECK(message_of(good, setting).find("HandEyeSetting.target_translation_sigma_m must be finite and > 0, got 0") !=
        std::string::npos);
  setting = {};
  setting.max_iterations = -1;
  CHECK(message_of(good, setting).find("max_iterations must be >= 0, got -1") != std::string::npos);
}
