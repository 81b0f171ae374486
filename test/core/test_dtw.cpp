// Dynamic time warping: exact 1-D DTW, the Sakoe-Chiba band and the (time, value) L1 variant.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

#include "swarm_forage/core/metrics/dtw.hpp"

namespace swarm_forage {
namespace {

using Seq = std::vector<double>;

/// Independent reference: the minimum over every warping path, enumerated recursively (tiny inputs).
double bruteForceDtw(const Seq& x, const Seq& y, std::optional<std::size_t> band = std::nullopt) {
  const std::size_t r = band.value_or(std::numeric_limits<std::size_t>::max());
  std::function<double(std::size_t, std::size_t)> best = [&](std::size_t i, std::size_t j) -> double {
    if ((i > j ? i - j : j - i) > r) return std::numeric_limits<double>::infinity();
    const double c = std::fabs(x[i] - y[j]);
    if (i == 0 && j == 0) return c;
    double m = std::numeric_limits<double>::infinity();
    if (i > 0) m = std::min(m, best(i - 1, j));
    if (j > 0) m = std::min(m, best(i, j - 1));
    if (i > 0 && j > 0) m = std::min(m, best(i - 1, j - 1));
    return c + m;
  };
  return best(x.size() - 1, y.size() - 1);
}

Seq randomSeq(std::mt19937& rng, std::size_t n) {
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  Seq s(n);
  for (double& v : s) v = u(rng);
  return s;
}

TEST(Dtw, KnownSmallExamples) {
  EXPECT_EQ(dtw({1, 2, 3}, {1, 2, 2, 3}), 0.0);  // the repeated 2 warps onto x's 2
  EXPECT_EQ(dtw({0, 0, 1}, {1}), 2.0);           // every x matches y0 = 1: 1 + 1 + 0
  EXPECT_EQ(dtw({1, 3}, {2}), 2.0);              // |1 - 2| + |3 - 2|
  EXPECT_EQ(dtw({0, 0}, {1, 1}), 2.0);           // diagonal: 1 + 1; any other path visits >= 2 cells of 1
  EXPECT_EQ(dtw({5}, {5}), 0.0);
  EXPECT_EQ(dtw({5}, {2}), 3.0);
  // x's peak (index 1) matches y's peak (index 3) through a warp of 2: cost 0.
  EXPECT_EQ(dtw({0, 1, 0, 0, 0}, {0, 0, 0, 1, 0}), 0.0);
}

TEST(Dtw, IdentityIsZeroAndDistanceIsSymmetric) {
  std::mt19937 rng(7);
  for (int k = 0; k < 20; ++k) {
    const Seq x = randomSeq(rng, 1 + rng() % 30), y = randomSeq(rng, 1 + rng() % 30);
    EXPECT_EQ(dtw(x, x), 0.0);
    EXPECT_EQ(dtw(x, y), dtw(y, x));  // bit for bit
    EXPECT_EQ(dtw(x, y, 3), dtw(y, x, 3));
    EXPECT_GT(dtw(x, y), 0.0);  // random reals: no two equal
  }
}

TEST(Dtw, MatchesEveryPathEnumerated) {
  std::mt19937 rng(11);
  for (int k = 0; k < 60; ++k) {
    const Seq x = randomSeq(rng, 1 + rng() % 6), y = randomSeq(rng, 1 + rng() % 6);
    EXPECT_NEAR(dtw(x, y), bruteForceDtw(x, y), 1e-12);
    const std::size_t band = rng() % 4;
    const std::size_t diff = x.size() > y.size() ? x.size() - y.size() : y.size() - x.size();
    EXPECT_NEAR(dtw(x, y, band), bruteForceDtw(x, y, std::max(band, diff)), 1e-12) << "band " << band;
  }
}

TEST(Dtw, BandNarrowsThePathAndIsWidenedToTheLengthDifference) {
  const Seq x = {0, 1, 0, 0, 0}, y = {0, 0, 0, 1, 0};
  EXPECT_EQ(dtw(x, y, 0), 2.0);  // diagonal only: |1 - 0| at i = 1 + |0 - 1| at i = 3
  EXPECT_EQ(dtw(x, y, 1), 2.0);  // the peaks are 2 apart: each peak meets a 0 somewhere -> 1 + 1
  EXPECT_EQ(dtw(x, y, 2), 0.0);  // the warp of 2 fits
  EXPECT_EQ(effectiveDtwBand(5, 2, 0), std::optional<std::size_t>(3));  // widened to |5 - 2|
  EXPECT_EQ(effectiveDtwBand(2, 5, 1), std::optional<std::size_t>(3));
  EXPECT_EQ(effectiveDtwBand(5, 5, 1), std::optional<std::size_t>(1));
  EXPECT_FALSE(effectiveDtwBand(5, 2, std::nullopt).has_value());
  // Band 0 between lengths 5 and 2 is widened to 3: the path (0,0), (1,0), (2,0), (3,0), (4,1) has
  // |i - j| <= 3 and costs 0 + 0 + 0 + 0 + |5 - 5| = 0.
  EXPECT_EQ(dtw({0, 0, 0, 0, 5}, {0, 5}, 0), 0.0);
  // Lengths 4 and 1: band 0 is widened to 3, exactly enough for the only path, (0..3, 0):
  // 1 + 2 + 3 + 4 = 10.
  EXPECT_EQ(dtw({1, 2, 3, 4}, {0}, 0), 10.0);
}

TEST(Dtw, FullBandEqualsExactAndNarrowBandsNeverGoBelowIt) {
  std::mt19937 rng(3);
  for (int k = 0; k < 30; ++k) {
    const Seq x = randomSeq(rng, 5 + rng() % 60), y = randomSeq(rng, 5 + rng() % 60);
    const double exact = dtw(x, y);
    const std::size_t longest = std::max(x.size(), y.size());
    EXPECT_EQ(dtw(x, y, longest), exact);
    EXPECT_EQ(dtw(x, y, longest - 1), exact);  // every cell already has |i - j| <= longest - 1
    EXPECT_EQ(dtw(x, y, std::numeric_limits<std::size_t>::max()), exact);
    double previous = std::numeric_limits<double>::infinity();
    for (std::size_t band : {0, 1, 2, 4, 8, 16}) {
      const double banded = dtw(x, y, band);
      EXPECT_GE(banded, exact) << "band " << band;
      EXPECT_LE(banded, previous) << "a wider band cannot cost more (band " << band << ")";
      previous = banded;
    }
  }
}

TEST(Dtw, LongSeriesStayExactWithABand) {
  // 2000 x 2000 cells. y is x delayed by 10 samples (holding x0 = 0 first) and x holds its value
  // from sample 1989 on, so both end on sin(19.89): the warp x0 <-> y0..y10, x_k <-> y_(k+10),
  // x_1990..1999 <-> y_1999 costs 0 and never leaves |i - j| <= 10. With a band of 9, y10 = 0 must meet
  // some x_i with i in [1, 19], all sin(0.01 i) > 0.
  Seq x(2000), y(2000);
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] = std::sin(0.01 * static_cast<double>(std::min<std::size_t>(i, 1989)));
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = std::sin(0.01 * static_cast<double>(i < 10 ? 0 : i - 10));
  EXPECT_EQ(dtw(x, y, 10), 0.0);
  EXPECT_GT(dtw(x, y, 9), 0.0);
  EXPECT_EQ(dtw(x, y), 0.0);
}

TEST(DtwTimeValue, L1OverTimeAndValuePoints) {
  const Seq t = {0, 1, 2};
  // Values alone warp to 0: x = [0,0,1], y = [0,1,1] -> (0,0), (1,0), (2,1), (2,2) all cost 0.
  EXPECT_EQ(dtw({0, 0, 1}, {0, 1, 1}), 0.0);
  // With time: the diagonal costs |0-0| + |0-1| + |1-1| = 1 (time differences 0); any warp step
  // costs >= 1 in time on top of a mismatch somewhere, e.g. (1,0) = |1-0| + 0 = 1 then (2,1) = 1.
  EXPECT_EQ(dtwTimeValue(t, {0, 0, 1}, t, {0, 1, 1}), 1.0);
  EXPECT_EQ(dtwTimeValue(t, {0, 0, 1}, t, {0, 1, 1}), dtwTimeValue(t, {0, 1, 1}, t, {0, 0, 1}));
  EXPECT_EQ(dtwTimeValue(t, {3, 1, 2}, t, {3, 1, 2}), 0.0);
  // Equal time stamps everywhere reduce it to 1-D DTW.
  std::mt19937 rng(5);
  for (int k = 0; k < 10; ++k) {
    const Seq x = randomSeq(rng, 1 + rng() % 20), y = randomSeq(rng, 1 + rng() % 20);
    EXPECT_EQ(dtwTimeValue(Seq(x.size(), 4.0), x, Seq(y.size(), 4.0), y), dtw(x, y));
  }
  // Different lengths: [(0,0), (1,0), (2,0)] vs [(0,0), (2,0)]: (1,0) must meet a point 1 s away -> 1.
  EXPECT_EQ(dtwTimeValue({0, 1, 2}, {0, 0, 0}, {0, 2}, {0, 0}), 1.0);
  // A band narrows the time-value DTW like the 1-D one.
  EXPECT_GE(dtwTimeValue(t, {0, 0, 1}, t, {0, 1, 1}, 0), 1.0);
}

TEST(Dtw, RejectsEmptyAndNonFiniteInput) {
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(dtw({}, {1.0}), std::invalid_argument);
  EXPECT_THROW(dtw({1.0}, {}), std::invalid_argument);
  EXPECT_THROW(dtw({1.0, nan}, {1.0}), std::invalid_argument);
  EXPECT_THROW(dtw({1.0}, {inf}), std::invalid_argument);
  EXPECT_THROW(dtwTimeValue({0, 1}, {1, 2}, {0}, {}), std::invalid_argument);
  EXPECT_THROW(dtwTimeValue({0}, {1, 2}, {0}, {1}), std::invalid_argument);  // time axis too short
  EXPECT_THROW(dtwTimeValue({nan}, {1}, {0}, {1}), std::invalid_argument);
}

}  // namespace
}  // namespace swarm_forage
