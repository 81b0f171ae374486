// GP-DPO controller (its task-allocation arithmetic: test_task_allocation.cpp): estimate seeding, task
// transitions on hand-built sensor streams (deliver, harvest, collect, abort), status task counts,
// split invariance and parameter validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "config_checks.hpp"
#include "sensor_readings.hpp"
#include "swarm_forage/core/controllers/gp_dpo.hpp"
#include "swarm_forage/core/controllers/task_allocation.hpp"
#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {
namespace {

struct Seen {
  int32_t id;
  float x, y;
};

/// Fills every robot's flattened line of sight with the blocks and caches in its LineOfSight rect.
void see(SensorData& s, std::vector<Seen> blocks, std::vector<Seen> caches) {
  s.clearLineOfSight();
  const auto fill = [&s](std::vector<Seen>& objects, std::vector<uint32_t>& offset, std::vector<int32_t>& id,
                         std::vector<float>& x, std::vector<float>& y) {
    std::sort(objects.begin(), objects.end(), [](const Seen& a, const Seen& b) { return a.id < b.id; });
    offset.push_back(0);
    for (std::size_t i = 0; i < s.size(); ++i) {
      const Rect r = LineOfSight{}.around(s.x[i], s.y[i]);
      for (const Seen& o : objects) {
        if (!r.contains(o.x, o.y)) continue;
        id.push_back(o.id);
        x.push_back(o.x);
        y.push_back(o.y);
      }
      offset.push_back(static_cast<uint32_t>(id.size()));
    }
  };
  fill(blocks, s.los_block_offset, s.los_block_id, s.los_block_x, s.los_block_y);
  fill(caches, s.los_cache_offset, s.los_cache_id, s.los_cache_x, s.los_cache_y);
  s.los_cache_blocks.assign(s.los_cache_id.size(), 5);
}

// ---- task_allocation.hpp ----------------------------------------------------------------------

TEST(GpDpo, EstimateSeedsInRangeForIdealAndTimeVarying) {
  for (bool varying : {false, true}) {
    GpDpoConfig c;
    c.time_varying = varying;
    const double g_lo = varying ? 2000 : 20000, s_lo = varying ? 1000 : 10000;
    EXPECT_DOUBLE_EQ(c.partitionReactivity(), varying ? 4.0 : 6.0);
    const GpDpoBatch whole(c, 3, 0, 200), part(c, 3, 150, 50);
    double g_sum = 0;
    for (uint32_t l = 0; l < 200; ++l) {
      const TaskEstimates& e = whole.estimates(l);
      ASSERT_GE(e[GpTask::kGeneralist], g_lo);
      ASSERT_LE(e[GpTask::kGeneralist], 2 * g_lo);
      for (GpTask t : {GpTask::kHarvester, GpTask::kCollector}) {
        ASSERT_GE(e[t], s_lo);
        ASSERT_LE(e[t], 2 * s_lo);
      }
      g_sum += e[GpTask::kGeneralist];
      EXPECT_DOUBLE_EQ(whole.partition(l), 0.5);
      if (l >= 150) {  // independent of the split
        ASSERT_EQ(std::memcmp(&e, &part.estimates(l - 150), sizeof e), 0);
      }
    }
    EXPECT_NEAR(g_sum / 200, 1.5 * g_lo, 0.1 * g_lo);  // uniform: mean in the middle
  }
}

// ---- one robot on hand-built streams ---------------------------------------------------------

class GpOne : public ::testing::Test {
 protected:
  void make(const GpDpoConfig& c, GpTask task) {
    gp_ = std::make_unique<GpDpoBatch>(c, 21, 0, 1);
    gp_->assignTask(0, task, 0);
    e0_ = gp_->estimates(0);
    s_.resize(1);
  }
  void place(float x, float y) {
    s_.x[0] = x;
    s_.y[0] = y;
  }
  GpDpoState step() {
    see(s_, blocks_, caches_);
    gp_->step(tick_++, s_, cmd_, status_);
    return gp_->state(0);
  }
  void carry(int32_t block, uint8_t event) {
    s_.carried_block[0] = block;
    s_.events[0] = event;
  }
  /// Vector to a block in view, pick it up, start transporting.
  void pickUp() {
    place(1.1f, 1.1f);
    blocks_ = {{7, 1.4f, 1.1f}};
    ASSERT_EQ(step(), GpDpoState::kVector);
    place(1.39f, 1.1f);
    s_.ground[0] = kBlockGround;
    ASSERT_EQ(step(), GpDpoState::kPickup);
    EXPECT_EQ(cmd_.request[0], kPickup);
    blocks_.clear();
    carry(7, kPickupDone);
    s_.ground[0] = kFloor;
  }
  /// From transport: into the nest, wander, drop; returns the tick of the drop done.
  uint64_t deliver() {
    s_.light_x[0] = 3.0f;
    EXPECT_EQ(step(), GpDpoState::kTransport);
    EXPECT_FLOAT_EQ(cmd_.left[0], 0.08f);  // CRW phototaxis
    s_.ground[0] = kNest;
    for (int k = 0; k < 25; ++k) EXPECT_EQ(step(), GpDpoState::kNestWander);
    EXPECT_EQ(step(), GpDpoState::kDrop);
    EXPECT_EQ(cmd_.request[0], kDrop);
    carry(-1, kDropDone);
    const GpDpoState st = step();  // leaves the nest (by wandering; the next goal comes once outside)
    EXPECT_TRUE(st == GpDpoState::kLeaveNest || st == GpDpoState::kVector) << gpDpoStateName(st);
    s_.events[0] = 0;
    return tick_ - 1;
  }
  void expectFinished(GpTask t, uint64_t at) {
    TaskEstimates e = e0_;
    e[t] = 0.2 * e0_[t] + 0.8 * static_cast<double>(at);  // task started at tick 0
    for (GpTask k : {GpTask::kGeneralist, GpTask::kHarvester, GpTask::kCollector})
      EXPECT_DOUBLE_EQ(gp_->estimates(0)[k], e[k]) << gpTaskName(k);
    const TaskEstimates& now = gp_->estimates(0);
    EXPECT_EQ(gp_->partition(0), partitionProbability(now[GpTask::kGeneralist], now[GpTask::kHarvester],
                                                      now[GpTask::kCollector], 6.0));
    EXPECT_EQ(gp_->taskStart(0), at);  // the next task starts at once
  }

  std::unique_ptr<GpDpoBatch> gp_;
  TaskEstimates e0_;
  SensorData s_;
  std::vector<Seen> blocks_, caches_;
  CommandData cmd_;
  ControllerStatus status_;
  uint64_t tick_ = 0;
};

TEST_F(GpOne, GeneralistDeliversToTheNest) {
  make(GpDpoConfig{}, GpTask::kGeneralist);
  pickUp();
  const uint64_t at = deliver();
  expectFinished(GpTask::kGeneralist, at);
}

TEST_F(GpOne, HarvesterDropsInTheCache) {
  make(GpDpoConfig{}, GpTask::kHarvester);
  pickUp();
  EXPECT_EQ(step(), GpDpoState::kTransport);  // no cache known: explores with its block
  EXPECT_EQ(cmd_.request[0], kNone);
  EXPECT_GT(cmd_.left[0] + cmd_.right[0], 0.0f);
  caches_ = {{500, 1.6f, 1.1f}};  // in sight, 0.21 m ahead: vectors to it
  EXPECT_EQ(step(), GpDpoState::kTransport);
  EXPECT_NE(gp_->caches().find(0, 500), nullptr);
  EXPECT_FLOAT_EQ(cmd_.left[0], 0.08f);  // vector force 8 cm/s
  EXPECT_FLOAT_EQ(cmd_.right[0], 0.08f);
  s_.ground[0] = kCacheGround;
  EXPECT_EQ(step(), GpDpoState::kCacheDrop);
  EXPECT_EQ(cmd_.request[0], kCacheDrop);
  EXPECT_EQ(cmd_.left[0], 0.0f);
  EXPECT_EQ(gp_->task(0), GpTask::kHarvester);
  carry(-1, kDropDone);
  EXPECT_EQ(step(), GpDpoState::kExplore);
  expectFinished(GpTask::kHarvester, tick_ - 1);
}

TEST_F(GpOne, CollectorPicksFromTheCacheAndDelivers) {
  make(GpDpoConfig{}, GpTask::kCollector);
  place(1.1f, 1.1f);
  blocks_ = {{7, 1.4f, 1.1f}};  // blocks do not interest a collector
  EXPECT_EQ(step(), GpDpoState::kExplore);
  EXPECT_EQ(gp_->target(0), -1);
  caches_ = {{500, 1.5f, 1.1f}};
  EXPECT_EQ(step(), GpDpoState::kVector);
  EXPECT_FLOAT_EQ(cmd_.left[0], 0.08f);  // 0.4 m straight ahead, vector force 8 cm/s
  EXPECT_FLOAT_EQ(cmd_.right[0], 0.08f);
  s_.ground[0] = kCacheGround;
  EXPECT_EQ(step(), GpDpoState::kCachePickup);
  EXPECT_EQ(cmd_.request[0], kCachePickup);
  carry(42, kPickupDone);
  s_.ground[0] = kFloor;
  const uint64_t at = deliver();
  expectFinished(GpTask::kCollector, at);
}

TEST_F(GpOne, CollectorForgetsACacheThatVanished) {
  make(GpDpoConfig{}, GpTask::kCollector);
  place(1.1f, 1.1f);
  caches_ = {{500, 1.5f, 1.1f}};
  ASSERT_EQ(step(), GpDpoState::kVector);
  place(2.9f, 1.1f);  // inside the (large) cache, its centre out of sight
  s_.ground[0] = kCacheGround;
  ASSERT_EQ(step(), GpDpoState::kCachePickup);
  s_.events[0] = kBlockVanished;
  EXPECT_EQ(step(), GpDpoState::kExplore);
  EXPECT_EQ(gp_->caches().size(0), 0u);
  EXPECT_EQ(gp_->task(0), GpTask::kCollector);
}

TEST_F(GpOne, HarvesterAbortsOnlyAtItsInterfaceAndDropsItsBlock) {
  GpDpoConfig c;
  c.abort_reactivity = 0;  // p = 1 / (1 + e^0) = 0.5 per tick at the interface
  make(c, GpTask::kHarvester);
  place(1.1f, 1.1f);
  for (int k = 0; k < 100; ++k) ASSERT_EQ(step(), GpDpoState::kExplore);  // looking for a block: no abort
  EXPECT_EQ(gp_->taskStart(0), 0u);
  pickUp();
  EXPECT_EQ(gp_->taskStart(0), 0u);
  GpDpoState st = GpDpoState::kTransport;
  for (int k = 0; k < 60 && st == GpDpoState::kTransport; ++k) {
    st = step();
    s_.events[0] = 0;
  }
  ASSERT_EQ(st, GpDpoState::kAbortDrop);
  const uint64_t at = tick_ - 1;
  EXPECT_EQ(cmd_.request[0], kDrop);  // a free block where it is
  EXPECT_EQ(cmd_.left[0], 0.0f);
  expectFinished(GpTask::kHarvester, at);
  EXPECT_EQ(step(), GpDpoState::kAbortDrop);  // until the world executed it
  carry(-1, kDropDone);
  EXPECT_EQ(step(), GpDpoState::kExplore);
}

TEST_F(GpOne, CollectorAbortsWhileHeadingToTheCache) {
  GpDpoConfig c;
  c.abort_reactivity = 0;
  make(c, GpTask::kCollector);
  place(1.1f, 1.1f);
  while (gp_->taskStart(0) == 0 && tick_ < 60) ASSERT_EQ(step(), GpDpoState::kExplore);
  ASSERT_GT(gp_->taskStart(0), 0u);
  expectFinished(GpTask::kCollector, tick_ - 1);
}

TEST_F(GpOne, GeneralistNeverAborts) {
  GpDpoConfig c;
  c.abort_reactivity = 0;
  make(c, GpTask::kGeneralist);
  pickUp();
  for (int k = 0; k < 300; ++k) {
    ASSERT_EQ(step(), GpDpoState::kTransport);
    s_.events[0] = 0;
  }
  EXPECT_EQ(gp_->task(0), GpTask::kGeneralist);
  EXPECT_EQ(gp_->taskStart(0), 0u);
}

TEST(GpDpo, FirstAllocationAndStatusTaskCounts) {
  SensorData s;
  s.resize(60);
  CommandData cmd;
  ControllerStatus status;
  GpDpoConfig c;
  c.partition_initial = 0.0;  // never partition: all generalists
  GpDpoBatch all_g(c, 1, 0, 60);
  all_g.step(0, s, cmd, status);
  EXPECT_EQ(status.tasks.generalists, 60u);
  c.partition_initial = 1.0;  // always partition: harvester or collector, half and half
  GpDpoBatch subs(c, 1, 0, 60);
  subs.step(0, s, cmd, status);
  EXPECT_EQ(status.tasks.generalists, 0u);
  EXPECT_EQ(status.tasks.harvesters + status.tasks.collectors, 60u);
  EXPECT_GT(status.tasks.harvesters, 15u);
  EXPECT_GT(status.tasks.collectors, 15u);
  for (uint32_t l = 0; l < 60; ++l) EXPECT_EQ(subs.lastSubtask(l), subs.task(l));

  GpDpoBatch gp(GpDpoConfig{}, 1, 3, 9);
  const uint8_t plan[9] = {0, 1, 2, 2, 1, 2, 0, 1, 2};  // GpTask: generalist 0, harvester 1, collector 2
  for (uint32_t l = 0; l < 9; ++l) gp.assignTask(l, static_cast<GpTask>(plan[l]), 0);
  s.threatened[4] = s.threatened[40] = 1;  // only robot 4 is in this range
  gp.step(1, s, cmd, status);
  EXPECT_EQ(status.tasks.generalists, 2u);
  EXPECT_EQ(status.tasks.harvesters, 3u);
  EXPECT_EQ(status.tasks.collectors, 4u);
  EXPECT_EQ(status.in_avoidance, 1u);
  // Each robot's task goes out with its commands (world/markers colours by it).
  ASSERT_EQ(cmd.task.size(), 9u);
  for (uint32_t l = 0; l < 9; ++l) EXPECT_EQ(cmd.task[l], plan[l]) << "robot " << l + 3;
  ASSERT_EQ(status.state_names.size(), static_cast<std::size_t>(GpDpoState::kCount));
  EXPECT_EQ(status.state_names[7], "cache_pickup");
  EXPECT_EQ(status.state_names[8], "cache_drop");
  EXPECT_EQ(status.state_names[9], "abort_drop");
  EXPECT_EQ(std::accumulate(status.state_counts.begin(), status.state_counts.end(), 0u), 9u);
  EXPECT_EQ(gp.name(), "gp_dpo");
}

/// Varied readings: per robot one block and one cache near it, and 40-tick windows putting the robot
/// on the block, near it (now and then briefly in a cache), in the nest, on another block, or in the
/// cache.
void fillSensors(SensorData& s, std::size_t n, uint64_t t) {
  s.resize(n);
  std::vector<Seen> blocks, caches;
  for (std::size_t i = 0; i < n; ++i) {
    const uint64_t h = mix64(i * 1000003u + t), w = mix64(i * 7919u + t / 40 + 0x5bd1e995u);
    const uint64_t e = mix64(i * 31u + (t / 150) * 1009u);
    const float bx = 2.1f + static_cast<float>(i % 6) * 3.0f + static_cast<float>((e >> 8) % 5) * 0.1f;
    const float by = 2.1f + static_cast<float>(i / 6) * 3.0f + static_cast<float>((e >> 16) % 5) * 0.1f;
    const bool block = e % 3 != 0, cache = (e >> 24) % 3 != 0;
    if (block) blocks.push_back({static_cast<int32_t>(i), bx, by});
    if (cache) caches.push_back({static_cast<int32_t>(1000 + i), bx, by + 0.3f});
    const uint64_t mode = (w >> 30) % 6;
    s.x[i] = mode == 0 ? bx : bx - 0.35f;
    s.y[i] = by;
    s.theta[i] = static_cast<float>((h >> 56) % 60) * 0.1f - 3.0f;
    const uint8_t short_cache = (t / 8) % 3 == 0 ? kCacheGround : kFloor;  // brief visits to a cache
    const uint8_t grounds[6] = {
        block ? kBlockGround : kFloor, short_cache, kNest, kBlockGround, kCacheGround, kFloor};
    s.ground[i] = grounds[mode];
    fillVariedReadings(s, i, h, w);
  }
  see(s, blocks, caches);
}

TEST(GpDpo, SplitInvariance) {
  GpDpoConfig c;
  c.time_varying = true;
  c.abort_reactivity = 1.0;  // frequent aborts
  const uint32_t n = 24, half = 13;
  GpDpoBatch whole(c, 77, 0, n), lo(c, 77, 0, half), hi(c, 77, half, n - half);
  SensorData s;
  CommandData cw, cl, ch;
  ControllerStatus sw, sl, sh;
  std::vector<bool> seen(static_cast<std::size_t>(GpDpoState::kCount), false), tasks(3, false);
  for (uint64_t t = 0; t < 1000; ++t) {
    fillSensors(s, n, t);
    whole.step(t, s, cw, sw);
    lo.step(t, s, cl, sl);
    hi.step(t, s, ch, sh);
    for (uint32_t i = 0; i < n; ++i) {
      const CommandData& part = i < half ? cl : ch;
      const GpDpoBatch& b = i < half ? lo : hi;
      const uint32_t l = i < half ? i : i - half;
      ASSERT_EQ(cw.left[i], part.left[l]) << "robot " << i << " tick " << t;
      ASSERT_EQ(cw.right[i], part.right[l]);
      ASSERT_EQ(cw.request[i], part.request[l]);
      ASSERT_EQ(cw.task[i], part.task[l]);
      ASSERT_EQ(whole.state(i), b.state(l));
      ASSERT_EQ(whole.task(i), b.task(l));
      ASSERT_EQ(whole.taskStart(i), b.taskStart(l));
      ASSERT_EQ(std::memcmp(&whole.estimates(i), &b.estimates(l), sizeof(TaskEstimates)), 0);
      ASSERT_EQ(whole.partition(i), b.partition(l));
      seen[static_cast<std::size_t>(whole.state(i))] = true;
      tasks[static_cast<std::size_t>(whole.task(i))] = true;
    }
    ASSERT_EQ(sw.in_avoidance, sl.in_avoidance + sh.in_avoidance);
    ASSERT_EQ(sw.tasks.generalists, sl.tasks.generalists + sh.tasks.generalists);
    ASSERT_EQ(sw.tasks.harvesters, sl.tasks.harvesters + sh.tasks.harvesters);
    ASSERT_EQ(sw.tasks.collectors, sl.tasks.collectors + sh.tasks.collectors);
    ASSERT_EQ(sw.tasks.generalists + sw.tasks.harvesters + sw.tasks.collectors, n);
    for (std::size_t k = 0; k < sw.state_counts.size(); ++k)
      ASSERT_EQ(sw.state_counts[k], sl.state_counts[k] + sh.state_counts[k]);
  }
  for (std::size_t k = 0; k < seen.size(); ++k)
    EXPECT_TRUE(seen[k]) << gpDpoStateName(static_cast<GpDpoState>(k));
  for (std::size_t k = 0; k < 3; ++k) EXPECT_TRUE(tasks[k]) << gpTaskName(static_cast<GpTask>(k));
}

TEST(GpDpo, ValidateRejectsOutOfRange) {
  EXPECT_NO_THROW(GpDpoConfig{}.validate());
  const auto expectReject = [](auto mutate, const std::string& field) {
    expectRejected<GpDpoBatch, GpDpoConfig>(mutate, field);
  };
  expectReject([](GpDpoConfig& c) { c.ideal_generalist_min = 0; }, "ideal_generalist_min");
  expectReject([](GpDpoConfig& c) { c.ideal_generalist_min = 50000; }, "ideal_generalist_min");
  expectReject([](GpDpoConfig& c) { c.ideal_subtask_max = 2e9; }, "ideal_subtask_max");
  expectReject([](GpDpoConfig& c) { c.varying_generalist_min = -1; }, "varying_generalist_min");
  expectReject([](GpDpoConfig& c) { c.varying_subtask_min = 3000; }, "varying_subtask_min");
  expectReject([](GpDpoConfig& c) { c.ideal_partition_reactivity = -1; }, "ideal_partition_reactivity");
  expectReject([](GpDpoConfig& c) { c.varying_partition_reactivity = 101; }, "varying_partition_reactivity");
  expectReject([](GpDpoConfig& c) { c.ema_weight = 1.5; }, "ema_weight");
  expectReject([](GpDpoConfig& c) { c.partition_initial = -0.1; }, "partition_initial");
  expectReject([](GpDpoConfig& c) { c.subtask_reactivity = std::nan(""); }, "subtask_reactivity");
  expectReject([](GpDpoConfig& c) { c.subtask_offset = -1; }, "subtask_offset");
  expectReject([](GpDpoConfig& c) { c.abort_reactivity = -1; }, "abort_reactivity");
  expectReject([](GpDpoConfig& c) { c.abort_offset = 1000; }, "abort_offset");
  expectReject([](GpDpoConfig& c) { c.dpo.pheromone_decay = 1.0; }, "pheromone_decay");
}

}  // namespace
}  // namespace swarm_forage
