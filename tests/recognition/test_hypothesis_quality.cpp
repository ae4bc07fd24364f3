// SPDX-License-Identifier: BSD-3-Clause
#include "nbs_catch.hpp"

#include <limits>
#include <span>
#include <vector>

#include "nbs/recognition/hypothesis_quality.hpp"

using namespace nbs;

namespace {
constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

TEST_CASE("hypothesis_quality: q_h of Eq. 3.10 on hand-built depth images", "[recognition]") {
  // A perfect match: every rendered pixel is a cluster pixel at the same depth.
  const std::vector<double> cluster{kNone, 0.30, 0.31, 0.32, kNone};
  HypothesisQuality q = hypothesis_quality(cluster, cluster, 0.0);
  CHECK(q.rendered == 3);
  CHECK(q.cluster == 3);
  CHECK(q.matching == 3);
  CHECK(q.q_h() == 1.0);
  // 4 rendered, 5 cluster, 2 within 0.25 m (0.125 and exactly 0.25 apart, binary-exact), one 0.375 m off, one
  // rendered outside the cluster.
  const std::vector<double> measured{1.0, 1.0, 1.0, 1.0, 1.0, kNone};
  const std::vector<double> rendered{1.125, 1.25, 1.375, kNone, kInf, 1.0};
  q = hypothesis_quality(rendered, measured, 0.25);
  CHECK(q.rendered == 4);
  CHECK(q.cluster == 5);
  CHECK(q.matching == 2);
  CHECK(q.q_h() == Approx(2.0 / 4.0 * (2.0 / 5.0) * (2.0 / 5.0)));
  // Nothing rendered, or an empty cluster: 0.
  const std::vector<double> none(3, kNone);
  CHECK(hypothesis_quality(none, std::span<const double>(cluster).subspan(0, 3), 0.01).q_h() == 0.0);
  CHECK(hypothesis_quality(std::span<const double>(cluster).subspan(0, 3), none, 0.01).q_h() == 0.0);
  CHECK(hypothesis_quality({}, {}, 0.01).q_h() == 0.0);
}

TEST_CASE("hypothesis_quality: bad input names the value", "[recognition]") {
  const std::vector<double> a(3, 0.3), b(2, 0.3);
  CHECK_THROWS_WITH(hypothesis_quality(a, b, 0.01), nbs_test::Contains("3 rendered pixels for 2 measured pixels"));
  CHECK_THROWS_WITH(hypothesis_quality(a, a, -0.01), nbs_test::Contains("tolerance_m"));
  CHECK_THROWS_WITH(hypothesis_quality(a, a, kNone), nbs_test::Contains("nan"));
}
