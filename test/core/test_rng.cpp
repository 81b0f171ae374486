// CounterRng: a pure function of (seed, stream, id, tick) and the draw index.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "swarm_forage/core/util/rng.hpp"

namespace swarm_forage {
namespace {

std::vector<uint64_t> draws(uint64_t seed, RngStream stream, uint64_t id, uint64_t tick, int n = 16) {
  CounterRng rng(seed, stream, id, tick);
  std::vector<uint64_t> out;
  for (int k = 0; k < n; ++k) out.push_back(rng.next());
  return out;
}

TEST(Rng, SameKeySameSequence) {
  EXPECT_EQ(draws(7, RngStream::kController, 12, 345), draws(7, RngStream::kController, 12, 345));
  CounterRng a(1, RngStream::kBlocks, 0, 0), b(1, RngStream::kBlocks, 0, 0);
  for (int k = 0; k < 1000; ++k) ASSERT_EQ(a.uniform(), b.uniform()) << k;
}

TEST(Rng, CachedIdKeyGivesTheSameSequence) {
  // Controllers keep idKey(seed, stream, id) per robot and build each tick's generator with atTick():
  // the same key chain as the four-part constructor, so the same draws.
  for (uint64_t seed : {0ULL, 7ULL, 0xffffffffULL})
    for (uint64_t id : {0ULL, 1ULL, 16383ULL})
      for (uint64_t tick : {0ULL, 1ULL, 299ULL, ~0ULL}) {
        CounterRng a(seed, RngStream::kController, id, tick);
        CounterRng b = CounterRng::atTick(CounterRng::idKey(seed, RngStream::kController, id), tick);
        for (int k = 0; k < 8; ++k) ASSERT_EQ(a.next(), b.next()) << seed << " " << id << " " << tick;
      }
  // The chain itself, written out: mix64(mix64(mix64(seed + g stream) + id) + tick k), then draw 1.
  const uint64_t g = 0x9e3779b97f4a7c15ULL, k = 0xd1b54a32d192ed03ULL;
  const uint64_t key = mix64(mix64(mix64(5 + g * 3) + 12) + 345 * k);
  EXPECT_EQ(CounterRng::atTick(CounterRng::idKey(5, RngStream::kController, 12), 345).next(), mix64(key + g));
}

TEST(Rng, DrawsWithinOneSequenceDiffer) {
  const std::vector<uint64_t> d = draws(7, RngStream::kController, 12, 345, 1000);
  for (std::size_t k = 1; k < d.size(); ++k) ASSERT_NE(d[k], d[k - 1]);
}

TEST(Rng, EveryKeyComponentChangesTheSequence) {
  const auto base = draws(7, RngStream::kController, 12, 345);
  EXPECT_NE(base, draws(8, RngStream::kController, 12, 345));  // seed
  EXPECT_NE(base, draws(7, RngStream::kPlacement, 12, 345));   // stream
  EXPECT_NE(base, draws(7, RngStream::kBlocks, 12, 345));
  EXPECT_NE(base, draws(7, RngStream::kCache, 12, 345));
  EXPECT_NE(base, draws(7, RngStream::kController, 13, 345));  // robot id
  EXPECT_NE(base, draws(7, RngStream::kController, 12, 346));  // tick
  // Swapping id and tick is a different key too.
  EXPECT_NE(draws(0, RngStream::kController, 1, 2), draws(0, RngStream::kController, 2, 1));
  // No two of many nearby keys share their first draw.
  std::vector<uint64_t> firsts;
  for (uint64_t id = 0; id < 50; ++id)
    for (uint64_t tick = 0; tick < 50; ++tick)
      firsts.push_back(draws(3, RngStream::kController, id, tick, 1)[0]);
  std::sort(firsts.begin(), firsts.end());
  EXPECT_EQ(std::adjacent_find(firsts.begin(), firsts.end()), firsts.end());
}

TEST(Rng, UniformInUnitIntervalWithMeanOneHalf) {
  CounterRng rng(123, RngStream::kController, 4, 5);
  const int n = 100000;
  double sum = 0, lo = 1, hi = 0;
  int below_tenth = 0;
  for (int k = 0; k < n; ++k) {
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    lo = std::min(lo, u);
    hi = std::max(hi, u);
    below_tenth += u < 0.1;
  }
  EXPECT_NEAR(sum / n, 0.5, 0.01);
  EXPECT_LT(lo, 0.001);
  EXPECT_GT(hi, 0.999);
  EXPECT_NEAR(below_tenth / static_cast<double>(n), 0.1, 0.01);
}

TEST(Rng, UniformRange) {
  CounterRng rng(9, RngStream::kPlacement, 0, 0);
  double sum = 0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double v = rng.uniform(-3.0, 5.0);
    ASSERT_GE(v, -3.0);
    ASSERT_LE(v, 5.0);  // [lo, hi): hi only by rounding
    sum += v;
  }
  EXPECT_NEAR(sum / n, 1.0, 0.1);
  CounterRng r2(9, RngStream::kPlacement, 0, 0);
  for (int k = 0; k < 100; ++k) {
    const double v = r2.uniform(2.0, 2.5);
    ASSERT_GE(v, 2.0);
    ASSERT_LE(v, 2.5);
  }
}

}  // namespace
}  // namespace swarm_forage
