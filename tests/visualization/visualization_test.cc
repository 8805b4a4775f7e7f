// The pictures' colour ranges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "colmap_ext/visualization/visualization.h"

namespace mpmvs {
namespace {

// RobustRange gives the quantiles of the finite positive values that a full sort gives,
// with invalid values (0, negative, NaN, infinite) mixed in and repeated values.
TEST(Visualization, RobustRangeIsTheQuantilesOfTheValidValues) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-1.f, 50.f);
  std::vector<float> values;
  for (int i = 0; i < 20000; ++i) values.push_back(i % 7 == 0 ? std::round(value(rng)) : value(rng));
  values[3] = std::numeric_limits<float>::quiet_NaN();
  values[4] = std::numeric_limits<float>::infinity();
  values[5] = 0.f;
  std::vector<float> valid;
  for (float x : values) {
    if (std::isfinite(x) && x > 0) valid.push_back(x);
  }
  std::sort(valid.begin(), valid.end());
  const size_t n = valid.size();
  for (const auto& q : std::vector<std::pair<double, double>>{{0.01, 0.99}, {0.0, 1.0}, {0.25, 0.75}, {0.9, 0.1}}) {
    double lo = 0, hi = 0;
    ASSERT_TRUE(RobustRange(values, q.first, q.second, &lo, &hi));
    EXPECT_EQ(lo, valid[static_cast<size_t>(q.first * (n - 1))]) << q.first;
    const double expected_hi = valid[static_cast<size_t>(q.second * (n - 1))];
    EXPECT_EQ(hi, expected_hi > lo ? expected_hi : lo + 1e-6) << q.second;
  }
  double lo = 0, hi = 0;
  ASSERT_TRUE(RobustRange(values, 0.5, 0.5, &lo, &hi));
  EXPECT_EQ(lo, valid[(n - 1) / 2]);
  EXPECT_EQ(hi, lo + 1e-6);  // an empty range is widened
  EXPECT_FALSE(RobustRange({0.f, -1.f, std::numeric_limits<float>::quiet_NaN()}, 0.01, 0.99, &lo, &hi));
}

}  // namespace
}  // namespace mpmvs
