// SightIndex: the line-of-sight query gives what a scan of every block gives, and its mask never
// hides a block or the cache, for robots anywhere (cell edges, off the arena) and blocks anywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "swarm_forage/core/world/sight_index.hpp"

namespace swarm_forage {
namespace {

/// What a robot at (x, y) sees: the free blocks whose centre lies in its view and in a cell of the
/// block grid (0.5 m cells over the arena, as BlockField counts them), in increasing id.
std::vector<int32_t> scanAll(const BlockField& f, const ArenaConfig& a, const Rect& view) {
  std::vector<int32_t> seen;
  const auto cells = [](double v, double extent) {
    const int c = static_cast<int>(v / 0.5);
    return c >= 0 && c < static_cast<int>(std::ceil(extent / 0.5));
  };
  for (std::size_t b = 0; b < f.size(); ++b) {
    const auto id = static_cast<int32_t>(b);
    if (f.carrier(id) == kFree && cells(f.x(id), a.width) && cells(f.y(id), a.height) &&
        view.contains(f.x(id), f.y(id)))
      seen.push_back(id);
  }
  return seen;
}

std::vector<double> near(double v, double step) {  // around v: edges of cells and the doubles next to them
  std::vector<double> out;
  for (int k = -12; k <= 12; ++k) {
    const double e = v + k * step / 2;
    out.insert(out.end(), {e, std::nextafter(e, -1e9), std::nextafter(e, 1e9)});
    const double edge = std::floor(e / step) * step;
    out.insert(out.end(), {edge, std::nextafter(edge, -1e9), std::nextafter(edge, 1e9)});
  }
  return out;
}

TEST(SightIndex, QueryAndMaskMatchAScanOfEveryBlock) {
  ArenaConfig a;
  a.width = 32;
  a.height = 16;
  a.n_blocks = 50;
  BlockField f;
  f.init(a, 5);
  // Blocks put down on the arena's edges, just off it, and on cell edges; some carried.
  const std::vector<std::pair<double, double>> odd = {{0, 0},      {-0.2, 5},      {-0.7, 5},
                                                      {32, 8},     {31.99, 15.99}, {10.0, 4.0},
                                                      {10.2, 4.4}, {5.6, 16.3},    {0.25, 0.5}};
  for (std::size_t k = 0; k < odd.size(); ++k) {
    f.pickUp(static_cast<int32_t>(k), 0);
    f.putDown(static_cast<int32_t>(k), odd[k].first, odd[k].second);
  }
  for (int32_t b = 20; b < 25; ++b) f.pickUp(b, 1);
  CacheConfig cc;
  cc.enabled = true;
  StaticCache cache;
  cache.init(a, cc);
  ASSERT_TRUE(cache.create(f));
  std::vector<int32_t> scratch;
  for (const LineOfSight los :
       {LineOfSight{0.2, 2}, LineOfSight{0.3, 0}, LineOfSight{1.0, 3}, LineOfSight{0.25, 1}}) {
    SightIndex index;
    index.build(los, a, f, cache);
    std::vector<std::pair<double, double>> robots;
    for (double x = -1; x <= 33; x += 0.07)
      for (double y = -1; y <= 17; y += 0.07) robots.emplace_back(x, y);
    const std::size_t spread = robots.size();  // over the arena; then crowded around blocks and cache
    for (std::size_t b = 0; b < f.size(); ++b)
      for (double x : near(f.x(static_cast<int32_t>(b)), los.cell))
        for (double y : near(f.y(static_cast<int32_t>(b)), los.cell)) robots.emplace_back(x, y);
    const Rect c = cache.area();
    for (double x : near(c.min_x, los.cell))
      for (double y : near(c.min_y, los.cell)) robots.emplace_back(x, y);
    for (double x : near(c.max_x, los.cell))
      for (double y : near(c.max_y, los.cell)) robots.emplace_back(x, y);
    std::size_t skipped = 0;
    for (std::size_t k = 0; k < robots.size(); ++k) {
      const auto [x, y] = robots[k];
      const Rect view = los.around(x, y);
      const std::vector<int32_t> expected = scanAll(f, a, view);
      std::vector<int32_t> got;
      index.forFreeBlocksIn(view, scratch, [&](int32_t b) { got.push_back(b); });
      ASSERT_EQ(got, expected) << "robot at " << x << ", " << y << " cell " << los.cell;
      if (index.maySee(x, y)) continue;
      skipped += k < spread ? 1 : 0;
      ASSERT_TRUE(expected.empty()) << "mask hides a block from " << x << ", " << y;
      ASSERT_FALSE(view.overlaps(c)) << "mask hides the cache from " << x << ", " << y;
    }
    if (los.cell == 0.2) {
      EXPECT_GT(skipped, spread / 2);  // the default sight skips most of the arena
    }
  }
}

}  // namespace
}  // namespace swarm_forage
