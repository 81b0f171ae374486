// Quirk (9) dynamics2d_contacts: hand-built pushes against what ARGoS' dynamics2d gives for the same bodies
// (foot-bots as dynamics2d_footbot_model.cpp builds them, stepped by its own chipmunk: docs/FIDELITY.md,
// "(9) dynamics2d_contacts"), no overlaps in a crowd, nothing moves a robot at rest but a push, and the
// same bodies for 1, 2 and 3 threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "sharing_pool.hpp"
#include "swarm_forage/core/controllers/crw.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {
namespace {

WorldConfig contactsConfig(uint32_t n, uint32_t seed = 1) {
  WorldConfig c;  // 32 x 16 m
  c.n_robots = n;
  c.seed = seed;
  c.quirks.set(Quirk::kDynamics2dContacts);
  return c;
}

// Robots on a line along x at y = 8, touching but 1 mm apart, robot 0 at x0; `speed[i]` is robot i's wheel
// speed (both wheels) and `heading[i]` its heading.
struct Line {
  World world;
  CommandData commands;
  Line(const std::vector<double>& speed, const std::vector<double>& heading, double x0 = 16.0)
      : world(contactsConfig(static_cast<uint32_t>(speed.size()))) {
    const double d = 2 * world.config().robot.radius + 0.001;
    commands.resize(speed.size());
    for (std::size_t i = 0; i < speed.size(); ++i) {
      world.setPose(static_cast<uint32_t>(i), x0 + d * static_cast<double>(i), 8.0, heading[i]);
      commands.left[i] = commands.right[i] = static_cast<float>(speed[i]);
    }
  }
  void run(int ticks) {
    for (int t = 0; t < ticks; ++t) world.step(commands, Throttling{});
  }
  double x(std::size_t i) const { return world.robots().x[i]; }
};

// ARGoS: one foot-bot at 0.1 m/s into one at rest moves both at 0.05 m/s (1 cm a tick at 5 ticks/s).
TEST(QuirkContacts, OnePusherMovesOneRobotAtRestAtHalfItsSpeed) {
  Line line({0.1, 0.0}, {0.0, 0.0});
  const double a0 = line.x(0), b0 = line.x(1);
  line.run(50);
  EXPECT_NEAR(line.x(1) - b0, 0.5, 0.02);
  EXPECT_NEAR(line.x(0) - a0, 0.5, 0.02);
  EXPECT_DOUBLE_EQ(line.world.robots().y[1], 8.0);  // straight on: no sideways drift
  EXPECT_TRUE(line.world.overlapFree());
}

// ARGoS: one pusher cannot move two robots at rest in a line (its 15 N against their 2 x 15 N).
TEST(QuirkContacts, OnePusherDoesNotMoveTwoRobotsAtRest) {
  Line line({0.1, 0.0, 0.0}, {0.0, 0.0, 0.0});
  const double b0 = line.x(1), c0 = line.x(2);
  line.run(50);
  EXPECT_EQ(line.x(1), b0);
  EXPECT_EQ(line.x(2), c0);
}

// ARGoS: two drives in a line push one robot at rest at their full speed (0.1 m/s), and three push two.
TEST(QuirkContacts, DrivesInALineOutnumberingTheRobotsAtRestPushThemAtFullSpeed) {
  {
    Line line({0.1, 0.1, 0.0}, {0.0, 0.0, 0.0});
    const double c0 = line.x(2);
    line.run(50);
    EXPECT_NEAR(line.x(2) - c0, 1.0, 0.03);
    EXPECT_TRUE(line.world.overlapFree());
  }
  {
    Line line({0.1, 0.1, 0.1, 0.0, 0.0}, {0.0, 0.0, 0.0, 0.0, 0.0});
    const double e0 = line.x(4);
    line.run(50);
    EXPECT_NEAR(line.x(4) - e0, 1.0, 0.05);
    EXPECT_TRUE(line.world.overlapFree());
  }
}

// ARGoS: head on at equal speeds neither moves; against one at 0.05 m/s both go the faster one's way at
// (0.1 - 0.05) / 2 = 0.025 m/s.
TEST(QuirkContacts, HeadOnTheFasterWinsByHalfTheDifference) {
  {
    Line line({0.1, 0.1}, {0.0, kPi});
    const double a0 = line.x(0), b0 = line.x(1);
    line.run(50);
    EXPECT_NEAR(line.x(0) - a0, 0.0, 0.002);
    EXPECT_NEAR(line.x(1) - b0, 0.0, 0.002);
  }
  {
    Line line({0.1, 0.05}, {0.0, kPi});
    const double b0 = line.x(1);
    line.run(50);
    EXPECT_NEAR(line.x(1) - b0, 0.25, 0.02);
  }
}

// ARGoS: at 0.3 rad off the line of centres (inside friction's atan(0.49)) the contact sticks and the robot
// at rest goes the pusher's way at half its speed (0.298 m in 30 ticks, no sideways drift); at 0.8 rad the
// pusher slides past, moving it 4.4 cm.
TEST(QuirkContacts, AnObliquePushSticksInsideTheFrictionConeAndSlidesOutside) {
  const auto run = [](double angle, double& moved, double& pusher_x, double& pushed_x) {
    WorldConfig c = contactsConfig(2);
    World world(c);
    const double d = 2 * c.robot.radius + 0.001;
    world.setPose(0, 16.0, 8.0, 0.0);
    world.setPose(1, 16.0 + d * std::cos(angle), 8.0 + d * std::sin(angle), 0.0);
    CommandData commands;
    commands.resize(2);
    commands.left[0] = commands.right[0] = 0.1f;
    for (int t = 0; t < 30; ++t) world.step(commands, Throttling{});
    moved = std::hypot(world.robots().x[1] - 16.0 - d * std::cos(angle),
                       world.robots().y[1] - 8.0 - d * std::sin(angle));
    pusher_x = world.robots().x[0];
    pushed_x = world.robots().x[1];
    EXPECT_TRUE(world.overlapFree());
  };
  double moved, pusher_x, pushed_x;
  run(0.3, moved, pusher_x, pushed_x);
  EXPECT_NEAR(moved, 0.3, 0.02);
  run(0.8, moved, pusher_x, pushed_x);
  EXPECT_LT(moved, 0.08);
  EXPECT_GT(pusher_x, pushed_x);  // it got past
}

// The walls do not give: a robot at rest against the east wall stays inside the arena.
TEST(QuirkContacts, ARobotAtRestAgainstAWallIsNotPushedThroughIt) {
  WorldConfig c = contactsConfig(2);
  World world(c);
  const double r = c.robot.radius, W = c.arena.width;
  world.setPose(0, W - r - 2 * r - 0.001, 8.0, 0.0);
  world.setPose(1, W - r, 8.0, 0.0);
  CommandData commands;
  commands.resize(2);
  commands.left[0] = commands.right[0] = 0.1f;
  for (int t = 0; t < 20; ++t) world.step(commands, Throttling{});
  EXPECT_EQ(world.robots().x[1], W - r);
  EXPECT_TRUE(world.overlapFree());
}

// Nothing but a push moves a robot at rest: touching ones at rest, and one beside a robot driving past.
TEST(QuirkContacts, ARobotAtRestIsNotMovedByNothing) {
  Line line({0.0, 0.0, 0.0}, {0.3, -1.0, 2.0});
  const std::vector<double> x0 = line.world.robots().x, th0 = line.world.robots().theta;
  line.run(30);
  EXPECT_EQ(line.world.robots().x, x0);
  EXPECT_EQ(line.world.robots().theta, th0);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(line.world.robots().y[i], 8.0);

  WorldConfig c = contactsConfig(2);
  World world(c);
  world.setPose(0, 10.0, 8.0, 0.0);
  world.setPose(1, 12.0, 8.0 + 2 * c.robot.radius + 0.002, 0.0);  // robot 0 drives past below it
  CommandData commands;
  commands.resize(2);
  commands.left[0] = commands.right[0] = 0.1f;
  for (int t = 0; t < 200; ++t) world.step(commands, Throttling{});
  EXPECT_GT(world.robots().x[0], 13.0);
  EXPECT_EQ(world.robots().x[1], 12.0);
  EXPECT_EQ(world.robots().y[1], 8.0 + 2 * c.robot.radius + 0.002);
}

// A crowd under CRW: never an overlap, every tick.
TEST(QuirkContacts, ACrowdNeverOverlaps) {
  const WorldConfig c = contactsConfig(1000, 7);
  World world(c);
  CrwBatch crw(CrwConfig{}, c.seed, 0, c.n_robots);
  SensorData sensors;
  CommandData commands;
  ControllerStatus status;
  for (int t = 0; t < 3000; ++t) {
    world.sense(sensors);
    crw.step(world.tick(), sensors, commands, status);
    world.step(commands, Throttling{});
    ASSERT_TRUE(world.overlapFree()) << "overlap after tick " << t;
  }
  EXPECT_GT(world.delivered(), 0u);
}

// The same bodies, bit for bit, for 1, 2 and 3 threads (N = 2,500: motion runs band by band in parallel).
TEST(QuirkContacts, BitIdenticalForAnyThreadCount) {
  std::vector<std::vector<double>> runs;
  for (unsigned threads : {1u, 2u, 3u}) {
    const WorldConfig c = contactsConfig(2500, 3);
    World world(c);
    world.setPool(sharingPool(threads));
    CrwBatch crw(CrwConfig{}, c.seed, 0, c.n_robots);
    SensorData sensors;
    CommandData commands;
    ControllerStatus status;
    for (int t = 0; t < 400; ++t) {
      world.sense(sensors);
      crw.step(world.tick(), sensors, commands, status);
      world.step(commands, Throttling{});
    }
    std::vector<double> bodies = world.robots().x;
    bodies.insert(bodies.end(), world.robots().y.begin(), world.robots().y.end());
    bodies.insert(bodies.end(), world.robots().theta.begin(), world.robots().theta.end());
    bodies.push_back(static_cast<double>(world.delivered()));
    runs.push_back(bodies);
  }
  EXPECT_EQ(0, std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(double)));
  EXPECT_EQ(0, std::memcmp(runs[0].data(), runs[2].data(), runs[0].size() * sizeof(double)));
}

}  // namespace
}  // namespace swarm_forage
