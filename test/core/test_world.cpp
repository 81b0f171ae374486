// World: collision-free motion under the real CRW controller, command validation, the condition's
// targets (carrying speed, every robot's speed, manipulation time), determinism per seed, and block
// delivery / respawn bookkeeping.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "swarm_forage/core/controllers/crw.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {
namespace {

WorldConfig makeConfig(uint32_t n_robots, uint32_t seed) {
  WorldConfig c;  // ArenaConfig defaults: 32 x 16 m, 50 blocks
  c.n_robots = n_robots;
  c.seed = seed;
  return c;
}

/// One lockstep tick: sense -> controller -> world.
struct Sim {
  World world;
  CrwBatch crw;
  SensorData sensors;
  CommandData commands;
  ControllerStatus status;

  Sim(const WorldConfig& c) : world(c), crw(CrwConfig{}, c.seed, 0, c.n_robots) {}
  StepResult tick(double throttle = 0.0) {
    world.sense(sensors);
    crw.step(world.tick(), sensors, commands, status);
    return world.step(commands, throttle);
  }
};

CommandData stopAll(std::size_t n) {
  CommandData c;
  c.first_id = 0;
  c.resize(n);
  return c;
}

// The requirement: robots never overlap each other, the walls or the arena bounds.
TEST(World, ThousandRobotsNeverOverlapUnderCrw) {
  Sim sim(makeConfig(1000, 7));
  ASSERT_TRUE(sim.world.overlapFree()) << "initial placement";
  const std::vector<double> x0 = sim.world.robots().x, y0 = sim.world.robots().y;
  uint64_t in_avoidance = 0;
  for (int t = 0; t < 10000; ++t) {
    sim.tick();
    in_avoidance += sim.status.in_avoidance;
    ASSERT_TRUE(sim.world.overlapFree()) << "overlap after tick " << t;
  }
  EXPECT_EQ(sim.world.tick(), 10000u);
  // The swarm really moved, interacted and foraged (otherwise the check above would be vacuous).
  double moved = 0;
  for (std::size_t i = 0; i < x0.size(); ++i)
    moved += std::hypot(sim.world.robots().x[i] - x0[i], sim.world.robots().y[i] - y0[i]);
  EXPECT_GT(moved / x0.size(), 1.0);
  EXPECT_GT(in_avoidance, 0u);
  EXPECT_GT(sim.world.delivered(), 0u);
}

TEST(World, StepRejectsCommandsNotCoveringAllRobots) {
  World world(makeConfig(10, 1));
  CommandData short_batch = stopAll(9);
  EXPECT_THROW(world.step(short_batch, 0.0), std::invalid_argument);
  CommandData offset_batch = stopAll(10);
  offset_batch.first_id = 1;
  EXPECT_THROW(world.step(offset_batch, 0.0), std::invalid_argument);
  CommandData empty;
  EXPECT_THROW(world.step(empty, 0.0), std::invalid_argument);
  EXPECT_EQ(world.tick(), 0u);
  CommandData all = stopAll(10);
  EXPECT_NO_THROW(world.step(all, 0.0));
  EXPECT_EQ(world.tick(), 1u);
}

/// Displacement of robot 0 driving straight along +y at full speed for `ticks` ticks under `throttle`,
/// optionally after picking up block 0 (robot placed on the block first, picked up without a condition).
double straightDisplacement(bool carry, Throttling throttle, int ticks) {
  World world(makeConfig(1, 3));
  const double bx = world.blocks().x(0), by = world.blocks().y(0);
  world.setPose(0, bx, by, kPi / 2);
  CommandData c = stopAll(1);
  if (carry) {
    c.request[0] = kPickup;
    world.step(c, 0.0);  // wheels stopped: the pick-up itself does not move the robot
    EXPECT_EQ(world.robots().carried[0], 0);
    EXPECT_EQ(world.carrying(), 1u);
    c.request[0] = kNone;
  }
  EXPECT_DOUBLE_EQ(world.robots().x[0], bx);
  EXPECT_DOUBLE_EQ(world.robots().y[0], by);
  const double vmax = world.config().robot.max_speed;
  c.left[0] = c.right[0] = static_cast<float>(vmax);
  for (int t = 0; t < ticks; ++t) world.step(c, throttle);
  EXPECT_NEAR(world.robots().x[0], bx, 1e-9);  // straight ahead, no drift
  return std::hypot(world.robots().x[0] - bx, world.robots().y[0] - by);
}

TEST(World, ThrottleSlowsOnlyCarryingRobots) {
  const int ticks = 20;
  const double free_run = straightDisplacement(false, 0.5, ticks);
  const double dt = WorldConfig{}.dt(), vmax = RobotConfig{}.max_speed;
  EXPECT_NEAR(free_run, ticks * vmax * dt, 1e-9);  // not carrying: throttle ignored
  EXPECT_NEAR(straightDisplacement(false, 0.0, ticks), free_run, 1e-12);

  const double carried_half = straightDisplacement(true, 0.5, ticks);
  EXPECT_NEAR(carried_half, (1 - 0.5) * free_run, 1e-9);
  EXPECT_NEAR(straightDisplacement(true, 0.2, ticks), (1 - 0.2) * free_run, 1e-9);
  EXPECT_NEAR(straightDisplacement(true, 0.0, ticks), free_run, 1e-9);
  EXPECT_NEAR(straightDisplacement(true, -0.5, ticks), 1.5 * free_run, 1e-9);  // a boost
  EXPECT_NEAR(straightDisplacement(true, 1.0, ticks), 0.0, 1e-12);             // full stop
}

TEST(World, SpeedTargetSlowsEveryRobotManipulationTimeNone) {
  const int ticks = 20;
  const double free_run = straightDisplacement(false, 0.0, ticks);
  for (const bool carry : {false, true}) {
    EXPECT_NEAR(straightDisplacement(carry, {0.5, ConditionTarget::kSpeed}, ticks), 0.5 * free_run, 1e-9);
    EXPECT_NEAR(straightDisplacement(carry, {-0.5, ConditionTarget::kSpeed}, ticks), 1.5 * free_run, 1e-9);
    // Speeds untouched, to the bit: the run without a condition moves exactly so.
    for (const double v : {-1.0, 0.5, 1.0})
      EXPECT_EQ(straightDisplacement(carry, {v, ConditionTarget::kManipulationTime}, ticks),
                straightDisplacement(carry, 0.0, ticks));
  }
}

/// Ticks robot 0 of `world` requests `request` before the world executes it under `throttle`.
int ticksUntilDone(World& world, uint8_t request, Throttling throttle) {
  CommandData c = stopAll(world.robots().size());
  c.request[0] = request;
  const int32_t before = world.robots().carried[0];
  for (int t = 0; t < 1000; ++t) {
    world.step(c, throttle);
    if (world.robots().carried[0] != before) return t;
    EXPECT_EQ(world.robots().events[0], 0) << "a robot still picking up or dropping is told nothing";
  }
  return -1;
}

TEST(World, ManipulationTimeHoldsPickUpsAndDropsByMaxZeroVTimesTenSeconds) {
  const Throttling half{0.5, ConditionTarget::kManipulationTime};
  const double tps = WorldConfig{}.ticks_per_second;
  for (const auto& [throttle, extra] :
       {std::pair<Throttling, int>{half, static_cast<int>(0.5 * 10 * tps)},
        {{1.0, ConditionTarget::kManipulationTime}, static_cast<int>(10 * tps)},
        {{-0.5, ConditionTarget::kManipulationTime}, 0},
        {{0.5, ConditionTarget::kCarrySpeed}, 0},
        {{0.5, ConditionTarget::kSpeed}, 0}}) {
    World world(makeConfig(1, 5));
    world.setPose(0, world.blocks().x(0), world.blocks().y(0), 0.0);
    EXPECT_EQ(ticksUntilDone(world, kPickup, throttle), extra) << "pick-up, V " << throttle.value;
    ASSERT_EQ(world.robots().carried[0], 0);
    EXPECT_TRUE(world.robots().events[0] & kPickupDone);
    const Rect nest = world.config().arena.nest();
    world.setPose(0, (nest.min_x + nest.max_x) / 2, (nest.min_y + nest.max_y) / 2, 0.0);
    EXPECT_EQ(ticksUntilDone(world, kDrop, throttle), extra) << "drop, V " << throttle.value;
    EXPECT_EQ(world.delivered(), 1u);
  }
}

std::vector<double> runPositions(uint32_t seed, int ticks) {
  Sim sim(makeConfig(300, seed));
  for (int t = 0; t < ticks; ++t) sim.tick();
  std::vector<double> out;
  const RobotBodies& r = sim.world.robots();
  for (std::size_t i = 0; i < r.size(); ++i) {
    out.push_back(r.x[i]);
    out.push_back(r.y[i]);
    out.push_back(r.theta[i]);
  }
  return out;
}

TEST(World, SameSeedIsBitIdenticalDifferentSeedsDiffer) {
  const std::vector<double> a = runPositions(42, 500);
  const std::vector<double> b = runPositions(42, 500);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(double))) << "same seed diverged";
  const std::vector<double> c = runPositions(43, 500);
  ASSERT_EQ(a.size(), c.size());
  EXPECT_NE(0, std::memcmp(a.data(), c.data(), a.size() * sizeof(double)));
}

TEST(World, DropInNestIsDeliveredAndRespawned) {
  World world(makeConfig(1, 5));
  const uint32_t n_blocks = world.config().arena.n_blocks;
  const Rect nest = world.config().arena.nest(), source = world.config().arena.source();
  world.setPose(0, world.blocks().x(0), world.blocks().y(0), 0.0);
  CommandData c = stopAll(1);
  c.request[0] = kPickup;
  EXPECT_EQ(world.step(c, 0.0).delivered, 0u);
  ASSERT_EQ(world.robots().carried[0], 0);
  EXPECT_EQ(world.blocks().carrier(0), 0);

  // A drop outside the nest puts the block down where the robot stands and is not counted.
  world.setPose(0, 16.0, 8.0, 0.0);
  c.request[0] = kDrop;
  EXPECT_EQ(world.step(c, 0.0).delivered, 0u);
  EXPECT_EQ(world.delivered(), 0u);
  EXPECT_EQ(world.blocks().carrier(0), -1);
  EXPECT_DOUBLE_EQ(world.blocks().x(0), 16.0);
  EXPECT_EQ(world.blocks().blockAt(16.0, 8.0), 0);
  c.request[0] = kPickup;
  world.step(c, 0.0);
  ASSERT_EQ(world.robots().carried[0], 0);

  // A drop in the nest is counted and the block reappears in the source.
  const double nx = (nest.min_x + nest.max_x) / 2, ny = (nest.min_y + nest.max_y) / 2;
  world.setPose(0, nx, ny, 0.0);
  c.request[0] = kDrop;
  EXPECT_EQ(world.step(c, 0.0).delivered, 1u);
  EXPECT_EQ(world.delivered(), 1u);
  EXPECT_EQ(world.robots().carried[0], -1);
  EXPECT_EQ(world.carrying(), 0u);
  EXPECT_EQ(world.blocks().size(), n_blocks);
  EXPECT_EQ(world.blocks().carrier(0), -1);
  EXPECT_TRUE(source.contains(world.blocks().x(0), world.blocks().y(0)));
  EXPECT_EQ(world.blocks().blockAt(world.blocks().x(0), world.blocks().y(0)), 0);
  EXPECT_EQ(world.blocks().blockAt(nx, ny), -1);
}

TEST(World, ForagingKeepsBlockCount) {
  Sim sim(makeConfig(400, 11));
  const uint32_t n_blocks = sim.world.config().arena.n_blocks;
  const Rect source = sim.world.config().arena.source();
  uint64_t delivered = 0;
  for (int t = 0; t < 6000; ++t) {
    delivered += sim.tick().delivered;
    ASSERT_EQ(sim.world.delivered(), delivered);
    ASSERT_EQ(sim.world.blocks().size(), n_blocks);
    uint32_t free_blocks = 0;
    for (std::size_t b = 0; b < sim.world.blocks().size(); ++b) {
      const int32_t carrier = sim.world.blocks().carrier(static_cast<int32_t>(b));
      if (carrier < 0) {
        ++free_blocks;
      } else {
        ASSERT_EQ(sim.world.robots().carried[carrier], static_cast<int32_t>(b));
      }
    }
    ASSERT_EQ(free_blocks, n_blocks - sim.world.carrying()) << "tick " << t;
  }
  EXPECT_GT(sim.world.delivered(), 0u);
  EXPECT_GT(sim.world.carrying(), 0u);
  // CRW only drops in the nest, so every free block lies in the source, findable where it is.
  for (std::size_t b = 0; b < sim.world.blocks().size(); ++b) {
    const auto id = static_cast<int32_t>(b);
    if (sim.world.blocks().carrier(id) >= 0) continue;
    EXPECT_TRUE(source.contains(sim.world.blocks().x(id), sim.world.blocks().y(id)));
    EXPECT_EQ(sim.world.blocks().blockAt(sim.world.blocks().x(id), sim.world.blocks().y(id)), id);
  }
}

}  // namespace
}  // namespace swarm_forage

namespace swarm_forage {
namespace {

TEST(World, SerializedBlockOpsFinishOnePickupAndOneDropPerTick) {
  WorldConfig c = makeConfig(3, 5);
  c.serialize_block_ops = true;
  World world(c);
  const Rect nest = world.config().arena.nest();
  const double nx = (nest.min_x + nest.max_x) / 2, ny = (nest.min_y + nest.max_y) / 2;
  for (uint32_t i = 0; i < 3; ++i) world.setPose(i, world.blocks().x(i), world.blocks().y(i), 0.0);
  CommandData cmd = stopAll(3);
  cmd.request[1] = cmd.request[2] = kPickup;
  world.step(cmd, 0.0);  // both ask at tick 0: the lower id first
  EXPECT_EQ(world.robots().carried[1], 1);
  EXPECT_EQ(world.robots().carried[2], -1);
  EXPECT_EQ(world.robots().events[2], 0) << "a waiting robot is not told its block vanished";
  cmd.request[0] = kPickup;  // robot 0 asks now, robot 2 has waited since tick 0: 2 goes first
  cmd.request[1] = kNone;
  world.step(cmd, 0.0);
  EXPECT_EQ(world.robots().carried[2], 2);
  EXPECT_EQ(world.robots().carried[0], -1);
  world.step(cmd, 0.0);
  EXPECT_EQ(world.robots().carried[0], 0);

  for (uint32_t i = 0; i < 3; ++i) world.setPose(i, nx, ny - 1.0 + i, 0.0);
  cmd.request = {kDrop, kDrop, kDrop};
  EXPECT_EQ(world.step(cmd, 0.0).delivered, 1u);  // one nest drop per tick
  EXPECT_EQ(world.step(cmd, 0.0).delivered, 1u);
  EXPECT_EQ(world.step(cmd, 0.0).delivered, 1u);
  EXPECT_EQ(world.carrying(), 0u);

  // Off (the default), all three would have finished at once.
  World free(makeConfig(3, 5));
  for (uint32_t i = 0; i < 3; ++i) free.setPose(i, free.blocks().x(i), free.blocks().y(i), 0.0);
  CommandData all = stopAll(3);
  all.request = {kPickup, kPickup, kPickup};
  free.step(all, 0.0);
  EXPECT_EQ(free.carrying(), 3u);
}

}  // namespace
}  // namespace swarm_forage
