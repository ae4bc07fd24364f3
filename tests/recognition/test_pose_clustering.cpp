// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <limits>
#include <random>

#include "nbs/core/detail/random.hpp"
#include "nbs/recognition/pose_clustering.hpp"
#include "nbs/recognition/pose_fusion.hpp"
#include "nbs_random.hpp"

using namespace nbs;

TEST_CASE("mean_rotation: exact for one rotation, sign-free, the midpoint of two about one axis", "[recognition]") {
  const Mat3 r = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  CHECK(rotation_angle_between(mean_rotation({r}), r) < 1e-9);
  const Mat3 a = Eigen::AngleAxisd(0.2, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 b = Eigen::AngleAxisd(0.6, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 mid = Eigen::AngleAxisd(0.4, Vec3::UnitZ()).toRotationMatrix();
  CHECK(rotation_angle_between(mean_rotation({a, b}), mid) < 1e-9);
  // Rotations near π about an axis (quaternions near ±w = 0 flip sign): still the right mean.
  const Mat3 c = Eigen::AngleAxisd(3.1, Vec3::UnitY()).toRotationMatrix();
  const Mat3 d = Eigen::AngleAxisd(-3.1, Vec3::UnitY()).toRotationMatrix();
  CHECK(rotation_angle_between(mean_rotation({c, d}), Eigen::AngleAxisd(3.14159265358979, Vec3::UnitY()).toRotationMatrix()) < 1e-6);
  CHECK(rotation_angle_between(a, b) == Approx(0.4));
  // Weights: 3:1 between 0.2 and 0.6 about z gives ≈ 0.3 (chordal mean of the half-angle quaternions).
  CHECK(rotation_angle_between(mean_rotation({a, b}, {3.0, 1.0}), Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix()) < 2e-3);
  CHECK_THROWS_WITH(mean_rotation({a, b}, {1.0}), nbs_test::Contains("1 weights for 2 rotations"));
}

TEST_CASE("cluster_poses: a known cluster among outliers comes first with its mean pose and summed score",
          "[recognition]") {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  const Pose truth = Eigen::Translation3d(0.3, -0.1, 0.05) * Eigen::AngleAxisd(0.9, Vec3(0.2, 1, -0.4).normalized());
  std::vector<PoseHypothesis> hyp;
  std::vector<Mat3> member_rotations;
  std::vector<double> member_weights;
  Vec3 member_t = Vec3::Zero();
  double member_score = 0;
  for (int i = 0; i < 20; ++i) {  // 20 members: ≤ ~2 mm and ≤ ~1.5° from the truth
    PoseHypothesis h;
    const Vec3 w = 0.01 * nbs_test::random_vec3(noise, rng);
    h.pose = Eigen::Translation3d(truth.translation() + 0.001 * nbs_test::random_vec3(noise, rng).cwiseMax(-1.5).cwiseMin(1.5)) *
             Eigen::AngleAxisd(truth.linear() * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix());
    h.score = 1.0 + (i % 3);
    hyp.push_back(h);
    member_rotations.push_back(h.pose.linear());
    member_weights.push_back(h.score);
    member_t += h.score * h.pose.translation();
    member_score += h.score;
  }
  for (int i = 0; i < 30; ++i) {  // outliers: uniform in a 1 m box, random rotations, scores up to 5
    PoseHypothesis h;
    const Vec3 t = nbs_test::random_vec3(detail::uniform01, rng) - Vec3(0.5, 0.5, 0.5) + Vec3(0, 0, 1);
    const double angle = 3.0 * detail::uniform01(rng);
    h.pose = Eigen::Translation3d(t) * Eigen::AngleAxisd(angle, nbs_test::random_vec3(noise, rng).normalized());
    h.score = 1.0 + 4.0 * detail::uniform01(rng);
    hyp.insert(hyp.begin() + std::min<std::ptrdiff_t>(2 * i, std::ssize(hyp)), h);  // interleaved
  }
  const std::vector<PoseHypothesis> c = cluster_poses(hyp, {0.01, 0.1});
  REQUIRE(!c.empty());
  CHECK(c[0].members == 20);
  CHECK(c[0].score == Approx(member_score));
  // The oracle: the score-weighted mean of the known members.
  CHECK((c[0].pose.translation() - member_t / member_score).norm() < 1e-12);
  CHECK(rotation_angle_between(c[0].pose.linear(), mean_rotation(member_rotations, member_weights)) < 1e-9);
  CHECK((c[0].pose.translation() - truth.translation()).norm() < 0.001);
  CHECK(rotation_angle_between(c[0].pose.linear(), truth.linear()) < 0.01);
  for (std::size_t i = 1; i < c.size(); ++i) CHECK(c[i].score <= c[i - 1].score);
  double total = 0;
  for (const auto& x : c) total += x.score;
  double expected = 0;
  for (const auto& x : hyp) expected += x.score;
  CHECK(total == Approx(expected));
  // Deterministic.
  const std::vector<PoseHypothesis> again = cluster_poses(hyp, {0.01, 0.1});
  REQUIRE(again.size() == c.size());
  for (std::size_t i = 0; i < c.size(); ++i) CHECK(again[i].pose.matrix() == c[i].pose.matrix());
}

TEST_CASE("cluster_poses: empty input, bad settings and scores", "[recognition]") {
  CHECK(cluster_poses({}).empty());
  CHECK_THROWS_WITH(cluster_poses({}, {-1.0, 0.1}), nbs_test::Contains("max_translation_m"));
  CHECK_THROWS_WITH(cluster_poses({}, {0.01, 4.0}), nbs_test::Contains("max_rotation_rad"));
  PoseHypothesis h;
  h.score = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(cluster_poses({h}), nbs_test::Contains("score of hypothesis 0"));
  h.score = -1.0;
  CHECK_THROWS_WITH(cluster_poses({h}), nbs_test::Contains("got -1"));
  h.score = 0.0;  // all-zero scores: the unweighted mean
  PoseHypothesis k = h;
  k.pose.translation() = Vec3(0.002, 0, 0);
  const auto z = cluster_poses({h, k});
  REQUIRE(z.size() == 1);
  CHECK(z[0].pose.translation().x() == Approx(0.001));
  CHECK_THROWS_WITH(mean_rotation({}), nbs_test::Contains("no rotations"));
}

TEST_CASE("PoseFusion: the mean pose of the largest cluster over views, outliers with high scores left out",
          "[recognition]") {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  const Pose truth = Eigen::Translation3d(0.2, 0.1, 0.0) * Eigen::AngleAxisd(1.2, Vec3::UnitZ());
  PoseFusion fusion({0.02, 0.2});
  CHECK(!fusion.fused());
  std::vector<Mat3> rotations;
  std::vector<double> weights;
  Vec3 t = Vec3::Zero();
  double score = 0.0;
  for (int view = 0; view < 15; ++view) {  // one hypothesis per view: ~3 mm and ~2° off the truth
    const Vec3 w = 0.035 * nbs_test::random_vec3(noise, rng).cwiseMax(-2.0).cwiseMin(2.0);
    PoseHypothesis h;
    h.pose = Eigen::Translation3d(truth.translation() + 0.003 * nbs_test::random_vec3(noise, rng).cwiseMax(-2.0).cwiseMin(2.0)) *
             Eigen::AngleAxisd(truth.linear() * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix());
    h.score = 0.5 + 0.1 * view;  // e.g. q_h
    fusion.add(h);
    rotations.push_back(h.pose.linear()), weights.push_back(h.score), t += h.score * h.pose.translation(), score += h.score;
    if (view % 5 == 2)  // a wrong match (the object turned half round, 5 cm off) with a high score, three times
      for (int k = 0; k < 1 + view / 5; ++k)
        fusion.add({Eigen::Translation3d(truth.translation() + Vec3(0.05, 0, 0)) *
                        Eigen::AngleAxisd(truth.linear() * Eigen::AngleAxisd(3.1, Vec3::UnitZ()).toRotationMatrix()),
                    10.0, 1});
  }
  CHECK(fusion.size() == 15 + 1 + 2 + 3);
  const std::optional<PoseHypothesis> f = fusion.fused();
  REQUIRE(f);
  // The wrong cluster has the higher summed score (60 against ~18) but 6 members against 15.
  CHECK(f->members == 15);
  CHECK(f->score == Approx(score));
  CHECK((f->pose.translation() - t / score).norm() < 1e-12);
  CHECK(rotation_angle_between(f->pose.linear(), mean_rotation(rotations, weights)) < 1e-9);
  const double et = (f->pose.translation() - truth.translation()).norm();
  const double er = rotation_angle_between(f->pose.linear(), truth.linear());
  INFO("fused error " << 1e3 * et << " mm, " << er * 180 / 3.14159265 << " deg");
  CHECK(et < 0.003);
  CHECK(er < 0.02);
  CHECK_THROWS_WITH(fusion.add({Pose::Identity(), -1.0, 1}), Catch::Contains("score must be finite and >= 0, got -1"));
  CHECK(fusion.size() == 21);
  CHECK_THROWS_WITH(PoseFusion({0.01, 4.0}), Catch::Contains("max_rotation_rad"));
}
