// Each condition target changes what it should and nothing else, in a whole swarm under CRW
// (docs/design-model.md, Environmental condition): carry_speed leaves robots that carry nothing alone, speed
// slows them too, manipulation_time moves every robot as without a condition until a pick-up, which then
// finishes exactly max(0, V) x 10 s later. The single-robot mechanics are in test_world.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "swarm_forage/core/run/simulation.hpp"

namespace swarm_forage {
namespace {

WorldConfig swarm() {
  WorldConfig c;  // 32 x 16 m
  c.n_robots = 8;
  c.seed = 4;
  return c;
}

bool samePoses(World& a, World& b) {
  const RobotBodies &p = a.robots(), &q = b.robots();
  const std::size_t bytes = p.size() * sizeof(double);
  return std::memcmp(p.x.data(), q.x.data(), bytes) == 0 && std::memcmp(p.y.data(), q.y.data(), bytes) == 0 &&
         std::memcmp(p.theta.data(), q.theta.data(), bytes) == 0;
}

/// The first tick at which a robot of a run without a condition requests a block operation, and which.
std::pair<uint64_t, uint32_t> firstRequest() {
  Simulation none(swarm(), "crw");
  for (uint64_t t = 0; t < 20000; ++t) {
    none.step();
    for (uint32_t i = 0; i < swarm().n_robots; ++i)
      if (none.commands().request[i] != kNone) return {t, i};
  }
  ADD_FAILURE() << "no robot asked for a pick-up";
  return {0, 0};
}

TEST(ConditionTarget, ManipulationTimeMovesRobotsAsWithoutConditionAndDelaysThePickUp) {
  const auto [request_tick, robot] = firstRequest();
  ASSERT_GT(request_tick, 0u);
  const Throttling v{0.5, ConditionTarget::kManipulationTime};
  const uint64_t hold = static_cast<uint64_t>(0.5 * kMaxManipulationSeconds * swarm().ticks_per_second);
  Simulation none(swarm(), "crw"), slow(swarm(), "crw");
  for (uint64_t t = 0; t <= request_tick; ++t) {
    none.step();
    slow.step(v);
    ASSERT_TRUE(samePoses(none.world(), slow.world())) << "speeds changed at tick " << t;
  }
  ASSERT_GE(none.world().robots().carried[robot], 0) << "without a condition the pick-up finishes at once";
  ASSERT_LT(slow.world().robots().carried[robot], 0);
  for (uint64_t t = request_tick + 1; t < request_tick + hold; ++t) {
    slow.step(v);
    ASSERT_LT(slow.world().robots().carried[robot], 0) << "picked up early, at tick " << t;
    ASSERT_EQ(slow.commands().request[robot], kPickup) << "the robot waits on its block, tick " << t;
  }
  slow.step(v);  // tick request_tick + hold: exactly 5 s (V 0.5 x 10 s) after the request
  EXPECT_EQ(slow.world().robots().carried[robot], none.world().robots().carried[robot]);
}

TEST(ConditionTarget, SpeedSlowsRobotsThatCarryNothingCarrySpeedDoesNot) {
  const auto [request_tick, robot] = firstRequest();  // nobody carries before
  (void)robot;
  Simulation none(swarm(), "crw"), carry(swarm(), "crw"), speed(swarm(), "crw");
  double moved_none = 0, moved_speed = 0;
  for (uint64_t t = 0; t < request_tick; ++t) {
    const std::vector<double> x0 = none.world().robots().x, xs = speed.world().robots().x;
    const std::vector<double> y0 = none.world().robots().y, ys = speed.world().robots().y;
    none.step();
    carry.step({0.5, ConditionTarget::kCarrySpeed});
    speed.step({0.5, ConditionTarget::kSpeed});
    ASSERT_TRUE(samePoses(none.world(), carry.world()))
        << "carry_speed moved a robot carrying nothing, tick " << t;
    for (uint32_t i = 0; i < swarm().n_robots; ++i) {
      moved_none += std::hypot(none.world().robots().x[i] - x0[i], none.world().robots().y[i] - y0[i]);
      moved_speed += std::hypot(speed.world().robots().x[i] - xs[i], speed.world().robots().y[i] - ys[i]);
    }
  }
  ASSERT_GT(moved_none, 0.0);
  // Every robot at half speed (turns and walls aside, the paths differ once they slow down).
  EXPECT_NEAR(moved_speed / moved_none, 0.5, 0.05);
  EXPECT_FALSE(samePoses(none.world(), speed.world()));
}

}  // namespace
}  // namespace swarm_forage
