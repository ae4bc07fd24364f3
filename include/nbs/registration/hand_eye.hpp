// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// Hand-eye calibration (Sec. 3.2.1, Eqs. 3.1–3.2): the flange → sensor transform X = T_FS of an eye-in-hand
/// sensor, from N ≥ 3 robot poses and the pose of a fixed calibration target measured by the sensor at each.
///
/// Convention. Pose pair i: T_WF_i (flange → world, the robot's reading) and T_ST_i (target → sensor, e.g. a
/// checkerboard pose from the camera). The target does not move, so for every i
///     T_WF_i · X · T_ST_i = T_WT                                                    (the pose loop)
/// and for every pair (i, j), from T_WF_i X T_ST_i = T_WF_j X T_ST_j,
///     A X = X B   with   A = T_WF_j⁻¹ · T_WF_i   (flange motion, in flange frame j),
///                        B = T_ST_j · T_ST_i⁻¹   (the same motion seen by the sensor, in sensor frame j).
/// The result feeds Eq. 3.1 (`sensor_from_flange(T_WF, X)`) and Eq. 3.2 (`flange_from_sensor(T_WS, X)`) of
/// nbs/driver/concepts.hpp.
///
/// Method.
/// 1. Closed form, Park & Martin (1994), over **all pairs** i < j: with α = log R_A and β = log R_B (rotation
///    vectors), α = R_X β; R_X = (MᵀM)^{-1/2} Mᵀ with M = Σ β αᵀ, computed as the SVD polar factor of Mᵀ with
///    det = +1. Pairs whose relative rotation exceeds π − 0.2 rad are left out of M (the sign of a rotation axis near
///    π is ambiguous). Translation: (R_A − I) t_X = R_X t_B − t_A stacked over all pairs, linear least squares.
///    T_WT: the chordal mean of the rotations and the mean of the translations of T_WF_i · X · T_ST_i.
/// 2. Refinement, Levenberg–Marquardt on the 12 parameters of X and T_WT (rotations perturbed on the right,
///    translations added; central-difference Jacobian). Residual of pose i, in the sensor frame:
///     r_i = (log(R_P_i · R_ST_iᵀ), t_P_i − t_ST_i),   P_i = X⁻¹ · T_WF_i⁻¹ · T_WT
///    (P_i the target pose predicted from the flange pose). Minimised: Σ_i r_iᵀ Σ_i⁻¹ r_i, where Σ_i is the
///    covariance of the target measurement (σ_r, σ_t) plus the flange-pose noise (σ_fr, σ_ft) propagated through
///    r_i at the closed-form estimate (first-order errors-in-variables; fixed during the iterations). Only steps
///    that lower this cost are taken, so it never ends above the closed form's.
///
/// Degeneracy. X is determined only if the relative flange rotations turn about at least two non-parallel axes.
/// With α_k the rotation vectors of the P pairs that enter R_X stacked as rows and s1 ≥ s2 ≥ s3 their singular values, the set is
/// refused when s2 / √P (the RMS rotation off the dominant axis, rad) is below `min_rotation_spread_rad`; the
/// message names the dominant axis (flange frame) — or, if even the RMS rotation angle is below it, says the
/// rotations are too small.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iomanip>
#include <numbers>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "nbs/core/error.hpp"
#include "nbs/core/types.hpp"

namespace nbs {

/// Settings of calibrate_hand_eye.
struct HandEyeSetting {
  /// Noise of the target measurement T_ST, per component: rotation (rad; the left factor exp(n) · R_ST, sensor frame)
  /// and translation (m). Defaults: a checkerboard seen from ≈ 0.5 m.
  double target_rotation_sigma_rad = 1e-3;
  double target_translation_sigma_m = 0.5e-3;
  /// Noise of the reported flange pose T_WF, per component, world frame (exp(n) · R_WF, t_WF + n), ≥ 0. Defaults: an
  /// industrial robot's repeatability-level errors. Only the ratios of the four sigmas change the estimate.
  double flange_rotation_sigma_rad = 0.3e-3;
  double flange_translation_sigma_m = 0.1e-3;
  /// The pose set is refused unless the RMS rotation off the dominant axis of the relative motions reaches this (rad).
  double min_rotation_spread_rad = 0.0175;  // ≈ 1°
  /// Levenberg–Marquardt iterations (Jacobian evaluations) at most; 0 returns the closed form.
  int max_iterations = 50;

  /// Throws InvalidArgument naming the field and its value.
  void validate() const {
    detail::require_positive("HandEyeSetting.target_rotation_sigma_rad", target_rotation_sigma_rad);
    detail::require_positive("HandEyeSetting.target_translation_sigma_m", target_translation_sigma_m);
    detail::require_non_negative("HandEyeSetting.flange_rotation_sigma_rad", flange_rotation_sigma_rad);
    detail::require_non_negative("HandEyeSetting.flange_translation_sigma_m", flange_translation_sigma_m);
    detail::require_positive("HandEyeSetting.min_rotation_spread_rad", min_rotation_spread_rad);
    detail::require(max_iterations >= 0, "HandEyeSetting.max_iterations must be >= 0, got ", max_iterations);
  }
};

/// The residual over the N poses (see the file comment): RMS angle of R_P · R_STᵀ (rad), RMS |t_P − t_ST| (m), and
/// the cost the refinement minimises divided by N, Σ_i r_iᵀ Σ_i⁻¹ r_i / N (≈ 6 − 12/N when the sigmas of the
/// setting are the true noise; much larger: the noise is larger than stated, or the poses are inconsistent).
struct HandEyeFit {
  double rms_rotation_rad = 0.0;
  double rms_translation_m = 0.0;
  double cost_per_pose = 0.0;
};

struct HandEyeResult {
  Pose T_FS = Pose::Identity();              ///< X, flange → sensor, after refinement
  Pose T_WT = Pose::Identity();              ///< target → world, after refinement
  Pose T_FS_closed_form = Pose::Identity();  ///< X of Park & Martin (step 1)
  Pose T_WT_closed_form = Pose::Identity();  ///< T_WT averaged with the closed-form X
  HandEyeFit closed_form;                    ///< residuals of (T_FS_closed_form, T_WT_closed_form)
  HandEyeFit refined;                        ///< residuals of (T_FS, T_WT)
  int iterations = 0;                        ///< Levenberg–Marquardt iterations run
  std::size_t pairs = 0;                     ///< relative motions (i < j) that entered R_X
  double rotation_spread_rad = 0.0;          ///< s2 / √P of the degeneracy rule
};

/// Solves A X = X B for X = T_FS (file comment). `flange_poses[i]` = T_WF_i, `target_poses[i]` = T_ST_i (metres).
/// Throws InvalidArgument (naming the problem and the value) if the sizes differ, fewer than 3 pairs are given, a
/// pose is not finite and rigid (naming its index), the setting is invalid, or the poses cannot determine X
/// (degeneracy rule). Pure function, thread-safe. Cost: O(N²) for the closed form, O(N) per iteration.
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
[[nodiscard]] HandEyeResult calibrate_hand_eye(std::span<const Pose> flange_poses, std::span<const Pose> target_poses,
                                               const HandEyeSetting& setting = {});

// ---- implementation -------------------------------------------------------------------------------------------

namespace detail::hand_eye {

/// Rotation vector (axis · angle, angle in [0, π]) of R.
[[nodiscard]] inline Vec3 rotation_log(const Mat3& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

[[nodiscard]] inline Mat3 rotation_exp(const Vec3& w) {
  const double angle = w.norm();
  return angle > 0.0 ? Mat3(Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()) : Mat3::Identity();
}

/// The rotation nearest to M in the Frobenius norm (SVD polar factor, det = +1).
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
[[nodiscard]] inline Mat3 nearest_rotation(const Mat3& M) {
  const Eigen::JacobiSVD<Mat3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

/// "(x, y, z)" with 3 decimals, the sign chosen so that the largest component is positive (an axis, not a direction).
[[nodiscard]] inline std::string format_axis(Vec3 a) {
  Eigen::Index k = 0;
  a.cwiseAbs().maxCoeff(&k);
  if (a(k) < 0.0) a = -a;
  a = (a * 1e3).array().round().matrix() * 1e-3 + Vec3::Zero();  // + 0: no "-0.000"
  std::ostringstream os;
  os << std::fixed << std::setprecision(3) << '(' << a.x() << ", " << a.y() << ", " << a.z() << ')';
  return os.str();
}

/// The state of the refinement: X and T_WT.
struct HandEyeState {
  Pose X, T_WT;

  /// Retraction: rotations R · exp(δ_r), translations t + δ_t; δ = (δ_r X, δ_t X, δ_r T_WT, δ_t T_WT).
  [[nodiscard]] HandEyeState plus(const Eigen::Matrix<double, 12, 1>& d) const {
    HandEyeState s = *this;
    s.X.linear() = X.linear() * rotation_exp(d.segment<3>(0));
    s.X.translation() += d.segment<3>(3);
    s.T_WT.linear() = T_WT.linear() * rotation_exp(d.segment<3>(6));
    s.T_WT.translation() += d.segment<3>(9);
    return s;
  }
};

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// Residual of pose i, unweighted: (log(R_P · R_STᵀ), t_P − t_ST), P = X⁻¹ · T_WF⁻¹ · T_WT.
[[nodiscard]] inline Vec6 hand_eye_residual(const HandEyeState& s, const Pose& T_WF, const Pose& T_ST) {
  const Pose P = s.X.inverse(Eigen::Isometry) * T_WF.inverse(Eigen::Isometry) * s.T_WT;
  Vec6 r;
  r.head<3>() = rotation_log(P.linear() * T_ST.linear().transpose());
  r.tail<3>() = P.translation() - T_ST.translation();
  return r;
}

/// The poses and, per pose, the whitening matrix W_i = L_i⁻¹ of the residual's covariance Σ_i = L_i L_iᵀ.
class HandEyeProblem {
public:
  /// Σ_i = diag(σ_r² I, σ_t² I) + J_i diag(σ_fr² I, σ_ft² I) J_iᵀ, J_i = ∂r_i / ∂(flange noise) at `at` (central
  /// differences; flange noise: R_WF → exp(n_r) R_WF, t_WF → t_WF + n_t, world frame).
  HandEyeProblem(std::span<const Pose> T_WF, std::span<const Pose> T_ST, const HandEyeSetting& setting,
                 const HandEyeState& at)
      : T_WF_(T_WF), T_ST_(T_ST) {
    constexpr double kStep = 1e-6;
    Vec6 flange_var, target_var;
    flange_var << Eigen::Vector3d::Constant(setting.flange_rotation_sigma_rad * setting.flange_rotation_sigma_rad),
        Eigen::Vector3d::Constant(setting.flange_translation_sigma_m * setting.flange_translation_sigma_m);
    target_var << Eigen::Vector3d::Constant(setting.target_rotation_sigma_rad * setting.target_rotation_sigma_rad),
        Eigen::Vector3d::Constant(setting.target_translation_sigma_m * setting.target_translation_sigma_m);
    whiten_.reserve(T_WF.size());
    for (std::size_t i = 0; i < T_WF.size(); ++i) {
      Mat6 J;
      for (int k = 0; k < 6; ++k) {
        const auto moved = [&](double h) {
          Pose F = T_WF[i];
          if (k < 3) F.linear() = rotation_exp(h * Vec3::Unit(k)) * F.linear();
          else F.translation()(k - 3) += h;
          return hand_eye_residual(at, F, T_ST[i]);
        };
        J.col(k) = (moved(kStep) - moved(-kStep)) / (2.0 * kStep);
      }
      const Mat6 cov = Mat6(target_var.asDiagonal()) + J * flange_var.asDiagonal() * J.transpose();
      whiten_.push_back(cov.llt().matrixL().solve(Mat6::Identity()));
    }
  }

  [[nodiscard]] std::size_t size() const { return T_WF_.size(); }

  /// Whitened residuals (6N): W_i · r_i.
  [[nodiscard]] Eigen::VectorXd residuals(const HandEyeState& s) const {
    Eigen::VectorXd r(static_cast<Eigen::Index>(6 * size()));
    for (std::size_t i = 0; i < size(); ++i)
      r.segment<6>(static_cast<Eigen::Index>(6 * i)) = whiten_[i] * hand_eye_residual(s, T_WF_[i], T_ST_[i]);
    return r;
  }

  [[nodiscard]] HandEyeFit fit(const HandEyeState& s) const {
    double rot = 0.0, trans = 0.0;
    for (std::size_t i = 0; i < size(); ++i) {
      const Vec6 ri = hand_eye_residual(s, T_WF_[i], T_ST_[i]);
      rot += ri.head<3>().squaredNorm();
      trans += ri.tail<3>().squaredNorm();
    }
    const auto n = static_cast<double>(size());
    return {std::sqrt(rot / n), std::sqrt(trans / n), residuals(s).squaredNorm() / n};
  }

private:
  std::span<const Pose> T_WF_, T_ST_;
  std::vector<Mat6> whiten_;
};

/// Levenberg–Marquardt (Marquardt's diagonal scaling) from `s`; returns the iterations run.
template <class = void>  // lazy: instantiated where called, not where included (docs/robustness.md)
inline int refine_hand_eye(HandEyeState& s, const HandEyeProblem& problem, int max_iterations) {
  using Vec12 = Eigen::Matrix<double, 12, 1>;
  using Mat12 = Eigen::Matrix<double, 12, 12>;
  constexpr double kStep = 1e-6;  // central differences: rad or m
  Eigen::VectorXd r = problem.residuals(s);
  double cost = r.squaredNorm(), lambda = 1e-3;
  int it = 0;
  while (it < max_iterations && cost > 0.0) {
    ++it;
    Eigen::MatrixXd J(r.size(), 12);
    for (int k = 0; k < 12; ++k) {
      Vec12 d = Vec12::Zero();
      d(k) = kStep;
      J.col(k) = (problem.residuals(s.plus(d)) - problem.residuals(s.plus(-d))) / (2.0 * kStep);
    }
    const Mat12 H = J.transpose() * J;
    const Vec12 g = J.transpose() * r;
    bool improved = false;
    double new_cost = cost;
    while (lambda < 1e12) {
      Mat12 damped = H;
      damped.diagonal() += lambda * (H.diagonal().array() + 1e-12).matrix();
      const Vec12 step = damped.ldlt().solve(-g);
      const HandEyeState trial = s.plus(step);
      const Eigen::VectorXd r_trial = problem.residuals(trial);
      new_cost = r_trial.squaredNorm();
      if (std::isfinite(new_cost) && new_cost < cost) {
        s = trial;
        r = r_trial;
        lambda = std::max(lambda / 10.0, 1e-12);
        improved = true;
        break;
      }
      lambda *= 10.0;
    }
    if (!improved) break;
    const double decrease = cost - new_cost;
    cost = new_cost;
    if (decrease <= 1e-12 * cost) break;  // converged: the last step changed the cost by < 1e-12 relative
  }
  return it;
}

}  // namespace detail::hand_eye

template <class>
inline HandEyeResult calibrate_hand_eye(std::span<const Pose> flange_poses, std::span<const Pose> target_poses,
                                        const HandEyeSetting& setting) {
  setting.validate();
  const std::size_t n = flange_poses.size();
  detail::require(n == target_poses.size(), "calibrate_hand_eye: flange_poses has ", n, " poses but target_poses has ",
                  target_poses.size(), " (one target pose per flange pose)");
  detail::require(n >= 3, "calibrate_hand_eye: needs at least 3 pose pairs, got ", n);
  for (std::size_t i = 0; i < n; ++i) {
    validate_pose(flange_poses[i], detail::concat("calibrate_hand_eye: flange_poses[", i, "]"));
    validate_pose(target_poses[i], detail::concat("calibrate_hand_eye: target_poses[", i, "]"));
  }

  // Relative motions of all pairs i < j: A = T_WF_j⁻¹ T_WF_i, B = T_ST_j T_ST_i⁻¹.
  const std::size_t pair_count = n * (n - 1) / 2;
  Eigen::MatrixXd axes(static_cast<Eigen::Index>(pair_count), 3);
  Eigen::MatrixXd C(static_cast<Eigen::Index>(3 * pair_count), 3);
  std::vector<Pose> As, Bs;
  As.reserve(pair_count), Bs.reserve(pair_count);
  Mat3 M = Mat3::Zero();
  HandEyeResult out;
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = 0; i < j; ++i) {
      const Pose A = flange_poses[j].inverse(Eigen::Isometry) * flange_poses[i];
      const Pose B = target_poses[j] * target_poses[i].inverse(Eigen::Isometry);
      const Vec3 alpha = detail::hand_eye::rotation_log(A.linear()), beta = detail::hand_eye::rotation_log(B.linear());
      if (std::max(alpha.norm(), beta.norm()) <= std::numbers::pi - 0.2) {
        M += beta * alpha.transpose();
        axes.row(static_cast<Eigen::Index>(out.pairs++)) = alpha.transpose();
      }
      As.push_back(A), Bs.push_back(B);
    }

  // Degeneracy: the relative rotations that enter R_X must turn about two non-parallel axes.
  detail::require(out.pairs >= 2, "calibrate_hand_eye: only ", out.pairs, " of ", pair_count,
                  " pose pairs turn by less than π − 0.2 rad (larger relative rotations are not used for R_X)");
  const Eigen::JacobiSVD<Eigen::MatrixXd> axes_svd(axes.topRows(static_cast<Eigen::Index>(out.pairs)),
                                                   Eigen::ComputeThinV);
  Vec3 s = Vec3::Zero();  // s1 ≥ s2 ≥ s3 / √P (fewer than 3 singular values when P = 2)
  s.head(axes_svd.singularValues().size()) = axes_svd.singularValues() / std::sqrt(static_cast<double>(out.pairs));
  out.rotation_spread_rad = s(1);
  detail::require(s.norm() >= setting.min_rotation_spread_rad,
                  "calibrate_hand_eye: the relative flange rotations are too small to determine X (RMS angle ",
                  s.norm(), " rad < min_rotation_spread_rad ", setting.min_rotation_spread_rad, ")");
  detail::require(s(1) >= setting.min_rotation_spread_rad,
                  "calibrate_hand_eye: all relative flange rotations are about one axis, ",
                  detail::hand_eye::format_axis(axes_svd.matrixV().col(0)), " in the flange frame, so X is not determined (RMS "
                  "rotation off that axis ", s(1), " rad < min_rotation_spread_rad ", setting.min_rotation_spread_rad,
                  "); rotate the flange about a second axis too");

  // Park & Martin: R_X = (MᵀM)^{-1/2} Mᵀ, the polar factor of Mᵀ; then (R_A − I) t_X = R_X t_B − t_A.
  Pose X = Pose::Identity();
  X.linear() = detail::hand_eye::nearest_rotation(M.transpose());
  Eigen::VectorXd d(C.rows());
  for (std::size_t k = 0; k < pair_count; ++k) {
    const auto row = static_cast<Eigen::Index>(3 * k);
    C.block<3, 3>(row, 0) = As[k].linear() - Mat3::Identity();
    d.segment<3>(row) = X.linear() * Bs[k].translation() - As[k].translation();
  }
  X.translation() = (C.transpose() * C).ldlt().solve(C.transpose() * d);

  // T_WT: mean of the N loop closures T_WF_i · X · T_ST_i.
  Mat3 rotation_sum = Mat3::Zero();
  Vec3 translation_sum = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Pose T_WT_i = flange_poses[i] * X * target_poses[i];
    rotation_sum += T_WT_i.linear();
    translation_sum += T_WT_i.translation();
  }
  Pose T_WT = Pose::Identity();
  T_WT.linear() = detail::hand_eye::nearest_rotation(rotation_sum);
  T_WT.translation() = translation_sum / static_cast<double>(n);

  detail::hand_eye::HandEyeState state{X, T_WT};
  const detail::hand_eye::HandEyeProblem problem(flange_poses, target_poses, setting, state);
  out.T_FS_closed_form = X;
  out.T_WT_closed_form = T_WT;
  out.closed_form = problem.fit(state);
  out.iterations = detail::hand_eye::refine_hand_eye(state, problem, setting.max_iterations);
  out.T_FS = state.X;
  out.T_WT = state.T_WT;
  out.refined = problem.fit(state);
  return out;
}

}  // namespace nbs
