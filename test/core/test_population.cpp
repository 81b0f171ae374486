// Population dynamics (docs/robustness-population.md): the processes' counts against their Poisson
// expectation, the FIFO repair queue, robots out of the swarm absent from sensing and collisions, a failing
// carrier's block left in the world, the parameters' validation and identity words.
#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <vector>

#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {
namespace {

CommandData still(std::size_t n) {
  CommandData c;
  c.resize(n);
  return c;
}

/// The expected interval between two operations of one process at `rate` per tick: a waiting time
/// floor(Exp(rate)) from the last operation, at least one tick (at most one operation per tick).
double meanInterval(double rate) {
  const double q = std::exp(-rate);
  return q / (1 - q) + (1 - q);  // E[floor(Exp)] + P(floor(Exp) = 0)
}

TEST(Population, DeathOnlyEndsWithTheExpectedCountWithinAPoissonBound) {
  const uint32_t n = 1000;
  const uint64_t ticks = 10000;
  const double rate = 0.05;
  const double expected = static_cast<double>(ticks) / meanInterval(rate);  // about 511 deaths
  PopulationConfig c;
  c.death = rate;
  double sum = 0;
  const int seeds = 20;
  for (int seed = 1; seed <= seeds; ++seed) {
    PopulationDynamics pd;
    pd.reset(c, static_cast<uint32_t>(seed), n);
    uint32_t deaths = 0;
    for (uint64_t t = 0; t < ticks; ++t) {
      const PopulationEvents& e = pd.update(t, [](uint32_t, bool) { return true; });
      ASSERT_LE(e.deaths.size(), 1u) << "at most one operation per process and tick";
      ASSERT_TRUE(e.births.empty() && e.malfunctions.empty() && e.repairs.empty());
      deaths += static_cast<uint32_t>(e.deaths.size());
    }
    EXPECT_EQ(pd.events().active, n - deaths);
    EXPECT_EQ(pd.events().present, n - deaths);
    // One run: within 4 sigma of a Poisson count.
    EXPECT_NEAR(deaths, expected, 4 * std::sqrt(expected)) << "seed " << seed;
    sum += deaths;
  }
  // The mean of 20 runs: within 4 sigma of the mean (tells the truncated waiting time from 1 / rate).
  EXPECT_NEAR(sum / seeds, expected, 4 * std::sqrt(expected / seeds));
}

TEST(Population, WorldDeathOnlyEndsWithTheExpectedActiveCount) {
  WorldConfig c;
  c.n_robots = 64;
  c.seed = 3;
  c.population.death = 0.01;
  World world(c);
  const uint64_t ticks = 3000;
  const CommandData stop = still(c.n_robots);
  for (uint64_t t = 0; t < ticks; ++t) world.step(stop, 0.0);
  const double expected = c.n_robots - static_cast<double>(ticks) / meanInterval(0.01);  // about 34
  const uint32_t active = world.population().events().active;
  EXPECT_NEAR(active, expected, 4 * std::sqrt(c.n_robots - expected));
  SensorData s;
  world.sense(s);
  ASSERT_EQ(s.active.size(), c.n_robots);
  uint32_t marked = 0;
  for (uint32_t i = 0; i < c.n_robots; ++i) {
    marked += s.active[i];
    EXPECT_EQ(s.active[i] != 0, world.population().presence(i) == Presence::kActive);
  }
  EXPECT_EQ(marked, active);
}

TEST(Population, RepairQueueIsFirstInFirstOutAndRobotsRejoinWhereTheyStopped) {
  WorldConfig c;
  c.n_robots = 8;
  c.seed = 11;
  c.population.malfunction = 0.05;
  c.population.repair = 0.03;
  World world(c);
  const std::vector<double> x0 = world.robots().x, y0 = world.robots().y;
  std::deque<uint32_t> queue;
  uint32_t malfunctions = 0, repairs = 0;
  const CommandData stop = still(c.n_robots);
  for (int t = 0; t < 3000; ++t) {
    world.step(stop, 0.0);
    const PopulationEvents& e = world.population().events();
    ASSERT_TRUE(e.deaths.empty() && e.births.empty());
    for (uint32_t id : e.malfunctions) {
      ASSERT_EQ(world.population().presence(id), Presence::kRepair);
      queue.push_back(id);
    }
    for (uint32_t id : e.repairs) {
      ASSERT_FALSE(queue.empty());
      EXPECT_EQ(id, queue.front()) << "tick " << t << ": the queue's head rejoins";
      queue.pop_front();
      EXPECT_EQ(world.robots().x[id], x0[id]);  // nobody moves: its spot is free
      EXPECT_EQ(world.robots().y[id], y0[id]);
    }
    malfunctions += static_cast<uint32_t>(e.malfunctions.size());
    repairs += static_cast<uint32_t>(e.repairs.size());
    ASSERT_EQ(std::vector<uint32_t>(queue.begin(), queue.end()),
              std::vector<uint32_t>(world.population().repairQueue().begin(),
                                    world.population().repairQueue().end()));
    ASSERT_EQ(e.active + e.queue, c.n_robots);
    ASSERT_EQ(e.present, c.n_robots);
  }
  EXPECT_GT(malfunctions, 20u);
  EXPECT_GT(repairs, 20u);
}

/// Steps `world` with its robots standing until a robot dies; returns its id (fails the test after 10,000
/// ticks).
uint32_t stepUntilDeath(World& world, const CommandData& commands) {
  for (int t = 0; t < 10000; ++t) {
    world.step(commands, 0.0);
    if (!world.population().events().deaths.empty()) return world.population().events().deaths[0];
  }
  ADD_FAILURE() << "nobody died";
  return 0;
}

TEST(Population, InactiveRobotsAreAbsentFromSensingCollisionsAndCommands) {
  WorldConfig c;
  c.n_robots = 2;
  c.seed = 4;
  c.population.death = 0.02;
  World world(c);
  const uint32_t dead = stepUntilDeath(world, still(2)), alive = 1 - dead;
  ASSERT_EQ(world.population().presence(alive), Presence::kActive);
  // The dead robot stands in the open; the live one is put half overlapping it, facing it.
  world.setPose(dead, 10.0, 8.0, 0.0);
  world.setPose(alive, 10.1, 8.0, kPi);
  SensorData s;
  world.sense(s);
  EXPECT_EQ(s.active[dead], 0);
  EXPECT_EQ(s.active[alive], 1);
  EXPECT_EQ(s.threatened[alive], 0) << "a dead robot is no obstacle";
  EXPECT_EQ(s.obstacle_x[alive], 0.f);
  EXPECT_TRUE(world.overlapFree()) << "only active robots have bodies";
  // Driving through it: the live robot moves as in the open; the dead one ignores its commands.
  CommandData drive = still(2);
  for (uint32_t i : {dead, alive}) drive.left[i] = drive.right[i] = 0.1f;
  world.step(drive, 0.0);
  EXPECT_NEAR(world.robots().x[alive], 10.1 - 0.1 * c.dt(), 1e-6);
  EXPECT_EQ(world.robots().x[dead], 10.0);
  EXPECT_EQ(world.robots().y[dead], 8.0);
}

TEST(Population, LineOfSightOfAnInactiveRobotIsEmpty) {
  WorldConfig c;
  c.n_robots = 2;
  c.seed = 4;
  c.line_of_sight = true;
  c.population.death = 0.02;
  World world(c);
  const uint32_t dead = stepUntilDeath(world, still(2));
  world.setPose(dead, world.blocks().x(0), world.blocks().y(0), 0.0);  // in sight of a block
  SensorData s;
  world.sense(s);
  EXPECT_EQ(s.los_block_offset[dead + 1] - s.los_block_offset[dead], 0u);
}

TEST(Population, AFailingCarriersBlockStaysInTheWorldWhereItStood) {
  for (const bool malfunction : {false, true}) {
    WorldConfig c;
    c.n_robots = 1;
    c.seed = 6;
    (malfunction ? c.population.malfunction : c.population.death) = 0.02;
    World world(c);
    const uint32_t n_blocks = world.config().arena.n_blocks;
    CommandData cmd = still(1);
    uint64_t left_at = 0;
    bool carried_before = false;
    for (int t = 0; t < 10000 && !left_at; ++t) {
      // Pick block 0 up, carry it to (16, 8) and stand there until the robot leaves.
      carried_before = world.robots().carried[0] >= 0;
      if (!carried_before) world.setPose(0, world.blocks().x(0), world.blocks().y(0), 0.0);
      if (carried_before && world.robots().x[0] != 16.0) world.setPose(0, 16.0, 8.0, 0.0);
      cmd.request[0] = carried_before ? kNone : kPickup;
      world.step(cmd, 0.0);
      const PopulationEvents& e = world.population().events();
      if (!e.deaths.empty() || !e.malfunctions.empty()) left_at = world.tick();
    }
    ASSERT_GT(left_at, 0u) << (malfunction ? "malfunction" : "death") << ": it never left";
    ASSERT_TRUE(carried_before) << "seed 6 leaves after the pick-up tick (else: choose another seed)";
    EXPECT_EQ(world.robots().carried[0], -1);
    EXPECT_EQ(world.carrying(), 0u);
    EXPECT_EQ(world.blocks().carrier(0), kFree) << "the block stays in the world, free";
    EXPECT_EQ(world.blocks().x(0), 16.0);
    EXPECT_EQ(world.blocks().y(0), 8.0);
    EXPECT_EQ(world.blocks().blockAt(16.0, 8.0), 0);
    EXPECT_EQ(world.blocks().size(), n_blocks);
    EXPECT_EQ(world.delivered(), 0u);
  }
}

TEST(Population, BirthRefillsADeadIdAtAFreeSpotHeadingZero) {
  WorldConfig c;
  c.n_robots = 16;
  c.seed = 2;
  c.population.death = 0.02;
  c.population.birth = 0.01;
  World world(c);
  uint32_t births = 0;
  const CommandData stop = still(c.n_robots);
  for (int t = 0; t < 4000; ++t) {
    std::vector<uint8_t> dead_before(c.n_robots);
    for (uint32_t i = 0; i < c.n_robots; ++i)
      dead_before[i] = world.population().presence(i) == Presence::kDead;
    world.step(stop, 0.0);
    const PopulationEvents& e = world.population().events();
    ASSERT_LE(e.present, c.n_robots) << "never above max_size";
    for (uint32_t id : e.births) {
      ++births;
      const bool died_now = std::find(e.deaths.begin(), e.deaths.end(), id) != e.deaths.end();
      EXPECT_TRUE(dead_before[id] || died_now) << "a newcomer takes a dead robot's id";
      EXPECT_EQ(world.robots().theta[id], 0.0);
      EXPECT_TRUE(world.config().arena.start().contains(world.robots().x[id], world.robots().y[id]));
      EXPECT_TRUE(world.robots().events[id] & kJoined);
      EXPECT_EQ(world.robots().carried[id], -1);
    }
    if (!e.births.empty() || t % 50 == 0) {
      ASSERT_TRUE(world.overlapFree()) << "tick " << t;
    }
  }
  EXPECT_GT(births, 5u);
}

TEST(Population, ValidationNamesTheParameterAndItsRange) {
  WorldConfig c;
  c.n_robots = 16;
  for (const double bad : {-1e-3, 1.5, std::nan("")}) {
    c.population = PopulationConfig{};
    c.population.repair = bad;
    try {
      c.validate();
      ADD_FAILURE() << "accepted repair " << bad;
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find("population/repair must be a rate per tick in [0, 1]"),
                std::string::npos)
          << e.what();
    }
  }
  c.population = PopulationConfig{};
  c.population.death = 1e-3;
  c.population.max_size = 15;  // below N
  EXPECT_THROW(c.validate(), ParameterError);
  c.population.max_size = 16;
  EXPECT_NO_THROW(c.validate());
}

TEST(Population, IdentityWordsOnlyWhenEnabled) {
  WorldConfig c;
  c.n_robots = 64;
  const std::string plain = c.describeConstants();
  EXPECT_EQ(plain.find("population"), std::string::npos);
  c.population.max_size = 64;  // no rate: still off
  EXPECT_EQ(c.describeConstants(), plain);
  c.population.death = 1e-4;
  c.population.malfunction = 1e-3;
  c.population.repair = 2e-3;
  EXPECT_EQ(c.describeConstants(),
            plain +
                " population/death=0.0001 population/birth=0 population/malfunction=0.001"
                " population/repair=0.002 population/max_size=64");
}

}  // namespace
}  // namespace swarm_forage
