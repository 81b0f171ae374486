// The world side of the DPO family: the static cache, line of sight and the block-vanished event.
#include <gtest/gtest.h>

#include <cmath>

#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {
namespace {

WorldConfig gpDpoWorld(uint32_t n) {
  WorldConfig c;
  c.n_robots = n;
  c.seed = 5;
  c.line_of_sight = true;
  c.cache.enabled = true;
  return c;
}

/// Parks every robot apart in an empty strip of the arena (y = 14.5, between nest and source).
void park(World& w) {
  for (uint32_t i = 0; i < w.robots().size(); ++i) w.setPose(i, 6.0 + 0.5 * i, 15.0, 0.0);
}

CommandData idle(const World& w) {
  CommandData c;
  c.resize(w.robots().size());
  return c;
}

uint32_t freeBlocks(const World& w) {
  uint32_t n = 0;
  for (std::size_t b = 0; b < w.blocks().size(); ++b)
    n += w.blocks().carrier(static_cast<int32_t>(b)) == kFree;
  return n;
}

TEST(StaticCache, CreatedWithTenPercentOfTheBlocksHalfwayBetweenNestAndSource) {
  World w(gpDpoWorld(4));
  ASSERT_TRUE(w.cache().exists());
  EXPECT_EQ(w.cache().size(), 5u);  // 10 % of 50
  // Nest centre x = 3.2, source centre x = 27.2: halfway 15.2; side 0.1 X = 3.2 m, on y = 8.
  EXPECT_NEAR(w.cache().center().x(), 15.2, 1e-9);
  EXPECT_NEAR(w.cache().center().y(), 8.0, 1e-9);
  EXPECT_NEAR(w.cache().area().width(), 3.2, 1e-9);
  EXPECT_EQ(freeBlocks(w), 45u);
  WorldConfig big = gpDpoWorld(4);
  big.arena = ArenaConfig{"96x48", 96, 48, 460};
  EXPECT_EQ(World(big).cache().size(), 46u);
}

TEST(StaticCache, GroundPickupDropAndDepletion) {
  World w(gpDpoWorld(3));
  park(w);
  const Vec2 c = w.cache().center();
  w.setPose(0, c.x(), c.y(), 0.0);
  w.setPose(1, c.x() + 0.5, c.y(), 0.0);
  SensorData s;
  w.sense(s);
  EXPECT_EQ(s.ground[0], kCacheGround);
  EXPECT_EQ(s.ground[2], kFloor);

  // Robots 0 and 1 take blocks in turn until the cache is gone.
  std::size_t expected = 5;
  for (int round = 0; w.cache().exists(); ++round) {
    ASSERT_LT(round, 10);
    CommandData cmd = idle(w);
    cmd.request[0] = kCachePickup;
    StepResult r = w.step(cmd, 0.0);
    EXPECT_EQ(r.delivered, 0u);
    w.sense(s);
    ASSERT_EQ(s.events[0], kPickupDone);
    ASSERT_GE(s.carried_block[0], 0);
    --expected;
    if (expected >= 2) {
      EXPECT_EQ(w.cache().size(), expected);
    }
    // Put it back down on the floor next to the cache so robot 0 can pick again.
    cmd = idle(w);
    cmd.request[0] = kDrop;
    w.setPose(0, c.x() - 2.5, c.y(), 0.0);  // outside the cache: a floor drop
    w.step(cmd, 0.0);
    w.setPose(0, c.x(), c.y(), 0.0);
  }
  // A pick-up that leaves one block removes the cache; that block is free on the floor at its centre.
  EXPECT_EQ(expected, 1u);
  const int32_t last = w.blocks().blockAt(c.x(), c.y());
  ASSERT_GE(last, 0);
  EXPECT_EQ(w.blocks().carrier(last), kFree);
  EXPECT_EQ(freeBlocks(w) + w.carrying() + w.cache().size(), 50u);

  // A cache pick-up with no cache reports the block vanished.
  CommandData cmd = idle(w);
  cmd.request[1] = kCachePickup;
  w.step(cmd, 0.0);
  w.sense(s);
  EXPECT_EQ(s.events[1], kBlockVanished);
  EXPECT_LT(s.carried_block[1], 0);
}

TEST(StaticCache, CacheDropIsNotPerformanceAndNestDropIs) {
  World w(gpDpoWorld(2));
  park(w);
  const Vec2 c = w.cache().center();
  w.setPose(0, c.x(), c.y(), 0.0);
  CommandData cmd = idle(w);
  cmd.request[0] = kCachePickup;
  w.step(cmd, 0.0);
  cmd.request[0] = kCacheDrop;
  EXPECT_EQ(w.step(cmd, 0.0).delivered, 0u);
  EXPECT_EQ(w.cache().size(), 5u);
  cmd.request[0] = kCachePickup;
  w.step(cmd, 0.0);
  const Rect nest = w.config().arena.nest();
  w.setPose(0, (nest.min_x + nest.max_x) / 2, (nest.min_y + nest.max_y) / 2, 0.0);
  cmd.request[0] = kDrop;
  EXPECT_EQ(w.step(cmd, 0.0).delivered, 1u);
  EXPECT_EQ(w.delivered(), 1u);
}

TEST(StaticCache, RecreationProbability) {
  CacheConfig cfg;
  cfg.enabled = true;
  StaticCache cache;
  cache.init(ArenaConfig{}, cfg);
  // 1 - exp(-0.05 * H / C): H = 4, C = 2 -> 1 - e^-0.1 = 0.0951626
  EXPECT_NEAR(cache.recreationProbability(4, 2), 0.09516258196, 1e-10);
  // C = 0: 1 - exp(-0.05 * H): H = 10 -> 1 - e^-0.5 = 0.3934693
  EXPECT_NEAR(cache.recreationProbability(10, 0), 0.39346934029, 1e-10);
  EXPECT_EQ(cache.recreationProbability(0, 0), 0.0);
  EXPECT_EQ(cache.recreationProbability(0, 7), 0.0);
}

TEST(StaticCache, RecreatedAtRandomOnlyWithHarvesters) {
  WorldConfig cfg = gpDpoWorld(2);
  cfg.cache.recreation_rate = 5.0;  // with H = 10, C = 1: p = 1 - e^-50, certain
  World w(cfg);
  park(w);
  const Vec2 c = w.cache().center();
  w.setPose(0, c.x(), c.y(), 0.0);
  CommandData cmd = idle(w);
  for (int k = 0; k < 4; ++k) {  // empty it: 5 -> 1 block left -> gone
    cmd.request[0] = kCachePickup;
    w.step(cmd, 0.0);
    cmd.request[0] = kDrop;
    w.setPose(0, 2.0, 15.0, 0.0);
    w.step(cmd, 0.0);
    w.setPose(0, c.x(), c.y(), 0.0);
  }
  ASSERT_FALSE(w.cache().exists());
  cmd = idle(w);
  for (int k = 0; k < 100; ++k) w.step(cmd, 0.0, TaskCounts{0, 0, 3});  // no harvesters: never
  EXPECT_FALSE(w.cache().exists());
  w.step(cmd, 0.0, TaskCounts{0, 10, 1});
  ASSERT_TRUE(w.cache().exists());
  EXPECT_EQ(w.cache().size(), 5u);
}

TEST(StaticCache, ValidationNamesTheParameter) {
  WorldConfig cfg = gpDpoWorld(2);
  cfg.cache.size_fraction = 0.6;  // would overlap nest and source
  try {
    World w(cfg);
    FAIL() << "a cache that does not fit was accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("cache size_fraction must be in (0, "), std::string::npos)
        << e.what();
  }
  cfg = gpDpoWorld(2);
  cfg.cache.block_fraction = 0.01;  // 0 blocks < min_blocks
  EXPECT_THROW(World{cfg}, ParameterError);
}

TEST(LineOfSight, ListsExactlyTheFreeBlocksWhoseCentreIsInView) {
  WorldConfig cfg = gpDpoWorld(1);
  cfg.cache.enabled = false;
  World w(cfg);
  const BlockField& blocks = w.blocks();
  const int32_t target = 0;
  w.setPose(0, blocks.x(target), blocks.y(target), 0.0);
  SensorData s;
  w.sense(s);
  ASSERT_EQ(s.los_block_offset.size(), 2u);
  const Rect view = LineOfSight{}.around(blocks.x(target), blocks.y(target));
  EXPECT_NEAR(view.width(), 1.0, 1e-9);
  std::vector<int32_t> expected;
  for (std::size_t b = 0; b < blocks.size(); ++b)
    if (view.contains(blocks.x(static_cast<int32_t>(b)), blocks.y(static_cast<int32_t>(b))))
      expected.push_back(static_cast<int32_t>(b));
  std::vector<int32_t> seen(s.los_block_id.begin() + s.los_block_offset[0],
                            s.los_block_id.begin() + s.los_block_offset[1]);
  EXPECT_EQ(seen, expected);
  EXPECT_FALSE(seen.empty());
  for (std::size_t k = 0; k < seen.size(); ++k) {
    EXPECT_FLOAT_EQ(s.los_block_x[k], static_cast<float>(blocks.x(seen[k])));
    EXPECT_FLOAT_EQ(s.los_block_y[k], static_cast<float>(blocks.y(seen[k])));
  }
  // A picked-up block leaves every line of sight.
  CommandData cmd = idle(w);
  cmd.request[0] = kPickup;
  w.step(cmd, 0.0);
  w.sense(s);
  EXPECT_EQ(std::count(s.los_block_id.begin(), s.los_block_id.end(), target), 0);
}

TEST(LineOfSight, CacheSeenWhenItsAreaOverlapsTheView) {
  World w(gpDpoWorld(2));
  park(w);
  const Rect area = w.cache().area();
  w.setPose(0, area.min_x - 0.3, 8.0, 0.0);  // view reaches 0.4-0.6 m right: overlaps
  w.setPose(1, area.min_x - 2.0, 8.0, 0.0);
  SensorData s;
  w.sense(s);
  EXPECT_EQ(s.los_cache_offset[1] - s.los_cache_offset[0], 1u);
  EXPECT_EQ(s.los_cache_offset[2] - s.los_cache_offset[1], 0u);
  EXPECT_EQ(s.los_cache_blocks[0], 5u);
}

TEST(LineOfSight, OffForCrwAndAFailedPickupSaysTheBlockVanished) {
  WorldConfig cfg;
  cfg.n_robots = 1;
  World w(cfg);
  w.setPose(0, 10.0, 10.0, 0.0);
  SensorData s;
  w.sense(s);
  EXPECT_FALSE(s.hasLineOfSight());
  CommandData cmd = idle(w);
  cmd.request[0] = kPickup;
  w.step(cmd, 0.0);
  w.sense(s);
  EXPECT_EQ(s.events[0], kBlockVanished);
}

}  // namespace
}  // namespace swarm_forage
