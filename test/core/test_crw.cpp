// CRW controller: state machine on hand-built sensor data, requests, status, range handling,
// split invariance, parameter validation, and the steering law.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/crw.hpp"
#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {
namespace {

/// Drives one CRW robot (a batch of one) through hand-built readings.
class CrwOne : public ::testing::Test {
 protected:
  CrwOne() : crw_(CrwConfig{}, 9, 0, 1) { s_.resize(1); }

  CrwState step() {
    crw_.step(tick_++, s_, cmd_, status_);
    return crw_.state(0);
  }
  /// Explores on the floor until exploration is long enough, then steps onto a block.
  void reachPickup() {
    for (uint32_t t = 0; t < CrwConfig{}.min_explore_ticks; ++t) ASSERT_EQ(step(), CrwState::kExplore);
    s_.ground[0] = kBlockGround;
    ASSERT_EQ(step(), CrwState::kPickup);
  }
  void reachTransport() {
    reachPickup();
    s_.events[0] = kPickupDone;
    s_.carried_block[0] = 4;
    s_.ground[0] = kFloor;
    ASSERT_EQ(step(), CrwState::kTransport);
    s_.events[0] = 0;
  }
  void reachDrop() {
    reachTransport();
    s_.ground[0] = kNest;
    ASSERT_EQ(step(), CrwState::kNestWander);
    for (uint32_t t = 1; t < CrwConfig{}.nest_wander_ticks; ++t) ASSERT_EQ(step(), CrwState::kNestWander);
    ASSERT_EQ(step(), CrwState::kDrop);
  }

  CrwBatch crw_;
  SensorData s_;
  CommandData cmd_;
  ControllerStatus status_;
  uint64_t tick_ = 0;
};

TEST_F(CrwOne, StartsExploringAndMoves) {
  EXPECT_EQ(step(), CrwState::kExplore);
  EXPECT_EQ(cmd_.size(), 1u);
  EXPECT_EQ(cmd_.first_id, 0u);
  EXPECT_EQ(cmd_.request[0], kNone);
  EXPECT_GT(cmd_.left[0] + cmd_.right[0], 0.0f);  // wander force points (nearly) ahead
}

TEST_F(CrwOne, ExploreToPickupOnlyAfterMinExploreTicks) {
  s_.ground[0] = kBlockGround;  // on a block from the very first tick
  for (uint32_t t = 0; t < CrwConfig{}.min_explore_ticks; ++t) {
    ASSERT_EQ(step(), CrwState::kExplore) << "tick " << t;
    ASSERT_EQ(cmd_.request[0], kNone);
  }
  EXPECT_EQ(step(), CrwState::kPickup);
  EXPECT_EQ(cmd_.request[0], kPickup);
  EXPECT_EQ(cmd_.left[0], 0.0f);  // stopped on the block
  EXPECT_EQ(cmd_.right[0], 0.0f);
  EXPECT_EQ(step(), CrwState::kPickup);  // keeps asking until the world executes it
  EXPECT_EQ(cmd_.request[0], kPickup);
}

TEST_F(CrwOne, ExploreIgnoresBlocksWhileCarrying) {
  for (uint32_t t = 0; t < CrwConfig{}.min_explore_ticks; ++t) step();
  s_.ground[0] = kBlockGround;
  s_.carried_block[0] = 2;
  EXPECT_EQ(step(), CrwState::kExplore);
  EXPECT_EQ(cmd_.request[0], kNone);
}

TEST_F(CrwOne, PickupToTransportOnPickupDone) {
  reachPickup();
  s_.events[0] = kPickupDone;
  s_.carried_block[0] = 4;
  EXPECT_EQ(step(), CrwState::kTransport);
  EXPECT_EQ(cmd_.request[0], kNone);
}

TEST_F(CrwOne, PickupToTransportOnCarriedAlone) {
  reachPickup();
  s_.carried_block[0] = 4;  // no event flag, but the block is carried
  EXPECT_EQ(step(), CrwState::kTransport);
}

TEST_F(CrwOne, PickupToExploreWhenBlockGone) {
  reachPickup();
  s_.ground[0] = kFloor;  // someone else took it
  EXPECT_EQ(step(), CrwState::kExplore);
  EXPECT_EQ(cmd_.request[0], kNone);
  EXPECT_GT(cmd_.left[0] + cmd_.right[0], 0.0f);  // wandering again
  // It keeps its exploration time: the next block is taken at once.
  s_.ground[0] = kBlockGround;
  EXPECT_EQ(step(), CrwState::kPickup);
}

TEST_F(CrwOne, TransportIsPhototaxisWithSoftTurns) {
  reachTransport();
  s_.light_x[0] = 3.0f;  // nest straight ahead
  EXPECT_EQ(step(), CrwState::kTransport);
  EXPECT_EQ(cmd_.request[0], kNone);
  EXPECT_FLOAT_EQ(cmd_.left[0], 0.08f);  // phototaxis force 8 cm/s
  EXPECT_FLOAT_EQ(cmd_.right[0], 0.08f);
  s_.light_x[0] = -3.0f;  // nest behind, a little left: a forced soft turn, whose inner wheel reverses
  s_.light_y[0] = 0.1f;
  step();
  EXPECT_FLOAT_EQ(cmd_.left[0], -0.1f);  // 8 (15 - 178) / 15 cm/s, clamped to the wheel limit
  EXPECT_FLOAT_EQ(cmd_.right[0], 0.1f);
}

TEST_F(CrwOne, TransportToNestWanderToDrop) {
  reachTransport();
  EXPECT_EQ(step(), CrwState::kTransport);  // still on the floor
  s_.ground[0] = kNest;
  EXPECT_EQ(step(), CrwState::kNestWander);
  EXPECT_EQ(cmd_.request[0], kNone);
  for (uint32_t t = 1; t < CrwConfig{}.nest_wander_ticks; ++t) {
    ASSERT_EQ(step(), CrwState::kNestWander) << "nest tick " << t;
    ASSERT_EQ(cmd_.request[0], kNone);
  }
  EXPECT_EQ(step(), CrwState::kDrop);
  EXPECT_EQ(cmd_.request[0], kDrop);
  EXPECT_EQ(cmd_.left[0], 0.0f);
  EXPECT_EQ(cmd_.right[0], 0.0f);
}

TEST_F(CrwOne, NestWanderBackToTransportWhenLeavingTheNest) {
  reachTransport();
  s_.ground[0] = kNest;
  ASSERT_EQ(step(), CrwState::kNestWander);
  s_.ground[0] = kFloor;
  EXPECT_EQ(step(), CrwState::kTransport);
}

TEST_F(CrwOne, DropToLeaveNestOnDropDone) {
  reachDrop();
  EXPECT_EQ(step(), CrwState::kDrop);  // not executed yet: ask again
  EXPECT_EQ(cmd_.request[0], kDrop);
  s_.events[0] = kDropDone;
  s_.carried_block[0] = -1;
  EXPECT_EQ(step(), CrwState::kLeaveNest);
  EXPECT_EQ(cmd_.request[0], kNone);
  s_.events[0] = 0;
  EXPECT_GT(cmd_.left[0] + cmd_.right[0], 0.0f);  // wanders out
  EXPECT_EQ(step(), CrwState::kLeaveNest);        // still in the nest
  s_.ground[0] = kFloor;
  EXPECT_EQ(step(), CrwState::kExplore);
  EXPECT_EQ(cmd_.request[0], kNone);
  // Exploration starts over: no pick-up before min_explore_ticks.
  s_.ground[0] = kBlockGround;
  for (uint32_t t = 1; t < CrwConfig{}.min_explore_ticks; ++t) ASSERT_EQ(step(), CrwState::kExplore);
  EXPECT_EQ(step(), CrwState::kPickup);
}

TEST_F(CrwOne, DropToLeaveNestOnEventAlone) {
  reachDrop();
  s_.events[0] = kDropDone;  // flag set, carried not yet cleared in this reading
  EXPECT_EQ(step(), CrwState::kLeaveNest);
}

TEST(Crw, StatusCountsAvoidanceAndStates) {
  const uint32_t n = 6;
  CrwBatch crw(CrwConfig{}, 1, 0, n);
  SensorData s;
  s.resize(n);
  s.threatened[1] = s.threatened[4] = s.threatened[5] = 1;
  s.obstacle_x[1] = s.obstacle_x[4] = s.obstacle_x[5] = 0.1f;
  CommandData cmd;
  ControllerStatus status;
  crw.step(0, s, cmd, status);
  EXPECT_EQ(status.in_avoidance, 3u);
  ASSERT_EQ(status.state_counts.size(), static_cast<std::size_t>(CrwState::kCount));
  ASSERT_EQ(status.state_names.size(), static_cast<std::size_t>(CrwState::kCount));
  EXPECT_EQ(status.state_names[0], "explore");
  EXPECT_EQ(status.state_names[static_cast<int>(CrwState::kLeaveNest)], "leave_nest");
  EXPECT_EQ(std::accumulate(status.state_counts.begin(), status.state_counts.end(), 0u), n);
  EXPECT_EQ(status.state_counts[static_cast<int>(CrwState::kExplore)], n);

  // Drive some robots into other states; counts still sum to n and status is not accumulated.
  for (uint64_t t = 1; t <= 50; ++t) crw.step(t, s, cmd, status);
  s.ground[0] = s.ground[2] = kBlockGround;
  s.threatened[4] = 0;
  crw.step(51, s, cmd, status);
  EXPECT_EQ(status.in_avoidance, 2u);
  EXPECT_EQ(status.state_counts[static_cast<int>(CrwState::kPickup)], 2u);
  EXPECT_EQ(status.state_counts[static_cast<int>(CrwState::kExplore)], n - 2);
  EXPECT_EQ(std::accumulate(status.state_counts.begin(), status.state_counts.end(), 0u), n);
  EXPECT_EQ(status.state_names.size(), static_cast<std::size_t>(CrwState::kCount));
}

TEST(Crw, AvoidanceTurnsAwayFromTheObstacle) {
  CrwBatch crw(CrwConfig{}, 1, 0, 1);
  SensorData s;
  s.resize(1);
  s.threatened[0] = 1;
  s.obstacle_x[0] = 0.15f;  // ahead and to the left
  s.obstacle_y[0] = 0.05f;
  CommandData cmd;
  ControllerStatus status;
  crw.step(0, s, cmd, status);
  EXPECT_GT(cmd.left[0], cmd.right[0]);  // turning right, away from it
}

/// Varied readings for n robots at tick t: a deterministic hash per (robot, tick) for the noisy
/// fields, and the ground held for 40-tick windows so that every state is reached.
void fillSensors(SensorData& s, std::size_t n, uint64_t t) {
  s.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const uint64_t h = mix64(i * 1000003u + t);
    const uint64_t g = mix64(i * 7919u + t / 40 + 0x5bd1e995u) % 3;
    s.x[i] = static_cast<float>(i);
    s.threatened[i] = h % 3 == 0;
    s.obstacle_x[i] = static_cast<float>((h >> 8) % 7) * 0.03f - 0.1f;
    s.obstacle_y[i] = static_cast<float>((h >> 16) % 5) * 0.04f - 0.08f;
    s.light_x[i] = static_cast<float>((h >> 24) % 11) * 0.5f - 2.5f;
    s.light_y[i] = static_cast<float>((h >> 32) % 13) * 0.4f - 2.4f;
    s.ground[i] = g == 0 ? kFloor : (g == 1 ? kBlockGround : kNest);
    const bool carrying = (h >> 40) % 3 == 0;
    s.carried_block[i] = carrying ? static_cast<int32_t>(i) : -1;
    s.events[i] = (h >> 48) % 4 == 0 ? (carrying ? kPickupDone : kDropDone) : 0;
  }
}

bool sameCommands(const CommandData& a, const CommandData& b) {
  return a.size() == b.size() && std::memcmp(a.left.data(), b.left.data(), a.size() * sizeof(float)) == 0 &&
         std::memcmp(a.right.data(), b.right.data(), a.size() * sizeof(float)) == 0 && a.request == b.request;
}

TEST(Crw, BatchReadsOnlyItsRange) {
  const uint32_t n = 16, first = 6, count = 5;
  CrwBatch a(CrwConfig{}, 3, first, count), b(CrwConfig{}, 3, first, count);
  EXPECT_EQ(a.firstId(), first);
  EXPECT_EQ(a.count(), count);
  SensorData s, garbled;
  CommandData ca, cb;
  ControllerStatus sa, sb;
  for (uint64_t t = 0; t < 200; ++t) {
    fillSensors(s, n, t);
    garbled = s;
    for (uint32_t i = 0; i < n; ++i) {
      if (i >= first && i < first + count) continue;
      garbled.threatened[i] = 1;
      garbled.obstacle_x[i] = 1e3f;
      garbled.light_x[i] = -7.f;
      garbled.ground[i] = static_cast<uint8_t>(t % 3);
      garbled.events[i] = 7;
      garbled.carried_block[i] = static_cast<int32_t>(t);
    }
    a.step(t, s, ca, sa);
    b.step(t, garbled, cb, sb);
    ASSERT_EQ(ca.first_id, first);
    ASSERT_EQ(ca.size(), count);
    ASSERT_TRUE(sameCommands(ca, cb)) << "tick " << t;
    ASSERT_EQ(sa.in_avoidance, sb.in_avoidance);
    ASSERT_EQ(sa.state_counts, sb.state_counts);
  }
}

TEST(Crw, SplitInvariance) {
  const uint32_t n = 24, half = 10;  // uneven split on purpose
  CrwBatch whole(CrwConfig{}, 77, 0, n);
  CrwBatch lo(CrwConfig{}, 77, 0, half), hi(CrwConfig{}, 77, half, n - half);
  SensorData s;
  CommandData cw, cl, ch;
  ControllerStatus sw, sl, sh;
  std::vector<bool> seen(static_cast<std::size_t>(CrwState::kCount), false);
  for (uint64_t t = 0; t < 1000; ++t) {
    fillSensors(s, n, t);
    whole.step(t, s, cw, sw);
    lo.step(t, s, cl, sl);
    hi.step(t, s, ch, sh);
    ASSERT_EQ(cl.first_id, 0u);
    ASSERT_EQ(ch.first_id, half);
    CommandData joined;
    joined.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
      const CommandData& part = i < half ? cl : ch;
      const uint32_t l = i < half ? i : i - half;
      joined.left[i] = part.left[l];
      joined.right[i] = part.right[l];
      joined.request[i] = part.request[l];
      const CrwState split_state = i < half ? lo.state(l) : hi.state(l);
      ASSERT_EQ(whole.state(i), split_state) << "robot " << i << " tick " << t;
      seen[static_cast<std::size_t>(whole.state(i))] = true;
    }
    ASSERT_TRUE(sameCommands(cw, joined)) << "tick " << t;
    ASSERT_EQ(sw.in_avoidance, sl.in_avoidance + sh.in_avoidance);
    ASSERT_EQ(sw.stalled, sl.stalled + sh.stalled);
    for (std::size_t k = 0; k < sw.state_counts.size(); ++k)
      ASSERT_EQ(sw.state_counts[k], sl.state_counts[k] + sh.state_counts[k]);
  }
  for (std::size_t k = 0; k < seen.size(); ++k)  // the comparison covered every state
    EXPECT_TRUE(seen[k]) << crwStateName(static_cast<CrwState>(k));
}

TEST(Crw, ValidateRejectsOutOfRange) {
  EXPECT_NO_THROW(CrwConfig{}.validate());
  auto expectReject = [](auto mutate, const char* what) {
    CrwConfig c;
    mutate(c);
    EXPECT_THROW(c.validate(), ParameterError) << what;
    EXPECT_THROW(CrwBatch(c, 0, 0, 1), ParameterError) << what;
  };
  expectReject([](CrwConfig& c) { c.wander_step = -0.1; }, "wander_step < 0");
  expectReject([](CrwConfig& c) { c.wander_step = 4.0; }, "wander_step > pi");
  expectReject([](CrwConfig& c) { c.wander_limit = -1.0; }, "wander_limit < 0");
  expectReject([](CrwConfig& c) { c.wander_limit = 0.0; }, "wander_limit 0 (fmod by 0)");
  expectReject([](CrwConfig& c) { c.wander_circle_radius = 3.0; }, "circle radius <= circle distance");
  expectReject([](CrwConfig& c) { c.wander_force = 0.0; }, "wander_force 0");
  expectReject([](CrwConfig& c) { c.wander_force = 101.0; }, "wander_force > 100");
  expectReject([](CrwConfig& c) { c.wander_free_scale = 0.0; }, "wander_free_scale 0");
  expectReject([](CrwConfig& c) { c.wander_free_scale = 1.5; }, "wander_free_scale > 1");
  expectReject([](CrwConfig& c) { c.avoidance_force = -1.0; }, "avoidance_force < 0");
  expectReject([](CrwConfig& c) { c.phototaxis_force = 0.0; }, "phototaxis_force 0");
  expectReject([](CrwConfig& c) { c.nest_wander_ticks = 100001; }, "nest_wander_ticks");
  expectReject([](CrwConfig& c) { c.min_explore_ticks = 100001; }, "min_explore_ticks");
  expectReject([](CrwConfig& c) { c.drive.max_speed = 0.0; }, "max_speed 0");
  expectReject([](CrwConfig& c) { c.drive.soft_turn_max = 0.0; }, "soft_turn_max 0");
  expectReject([](CrwConfig& c) { c.drive.hard_turn_speed = 0.2; }, "hard_turn_speed > max_speed");
  expectReject([](CrwConfig& c) { c.wander_force = std::nan(""); }, "wander_force NaN");
  try {
    CrwConfig c;
    c.wander_free_scale = 2.0;
    c.validate();
    FAIL() << "no exception";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("wander_free_scale"), std::string::npos) << e.what();
  }
}

// ---- steer() ---------------------------------------------------------------------------------

TEST(Steer, ZeroForceGivesZeroWheels) {
  const DriveConfig cfg;
  for (bool soft : {false, true}) {
    const WheelSpeeds w = steer(Vec2(0, 0), cfg, soft);
    EXPECT_EQ(w.left, 0.0f);
    EXPECT_EQ(w.right, 0.0f);
  }
}

TEST(Steer, StraightForceGivesEqualWheelsWithinMaxSpeed) {
  const DriveConfig cfg;
  WheelSpeeds w = steer(Vec2(6.3, 0), cfg, false);  // 6.3 cm/s
  EXPECT_FLOAT_EQ(w.left, 0.063f);
  EXPECT_FLOAT_EQ(w.right, 0.063f);
  w = steer(Vec2(50, 0), cfg, false);  // far above the limit
  EXPECT_FLOAT_EQ(w.left, w.right);
  EXPECT_LE(w.left, cfg.max_speed + 1e-7);
  EXPECT_FLOAT_EQ(w.left, static_cast<float>(cfg.max_speed));
}

TEST(Steer, SmallLeftErrorSpeedsUpTheRightWheel) {
  const DriveConfig cfg;
  const double err = deg2rad(5);
  const WheelSpeeds w = steer(Vec2(6 * std::cos(err), 6 * std::sin(err)), cfg, false);
  EXPECT_GT(w.right, w.left);
  EXPECT_GT(w.left, 0.0f);  // a soft turn: both wheels forward
  const double f = (cfg.soft_turn_max - err) / cfg.soft_turn_max;
  EXPECT_NEAR(w.left, 0.06 * f, 1e-6);  // v f, v (2 - f): 0.04 and 0.08 m/s, within max_speed
  EXPECT_NEAR(w.right, 0.06 * (2 - f), 1e-6);
  // Mirror image to the right.
  const WheelSpeeds m = steer(Vec2(6 * std::cos(err), -6 * std::sin(err)), cfg, false);
  EXPECT_FLOAT_EQ(m.left, w.right);
  EXPECT_FLOAT_EQ(m.right, w.left);
}

TEST(Steer, FastSoftTurnClampsEachWheel) {
  const DriveConfig cfg;
  const double err = deg2rad(5);  // v = 0.08: v (2 - f) = 0.107 > max_speed: that wheel alone is clamped
  const WheelSpeeds w = steer(Vec2(8 * std::cos(err), 8 * std::sin(err)), cfg, false);
  const double f = (cfg.soft_turn_max - err) / cfg.soft_turn_max;
  EXPECT_NEAR(w.right, cfg.max_speed, 1e-7);
  EXPECT_NEAR(w.left, 0.08 * f, 1e-7);
}

TEST(Steer, SoftTurnNeverExceedsMaxSpeed) {
  const DriveConfig cfg;
  for (double deg = -180; deg <= 180; deg += 2.5) {
    for (bool soft : {false, true}) {
      const WheelSpeeds w = steer(Vec2(9 * std::cos(deg2rad(deg)), 9 * std::sin(deg2rad(deg))), cfg, soft);
      EXPECT_LE(std::fabs(w.left), cfg.max_speed + 1e-7) << deg;
      EXPECT_LE(std::fabs(w.right), cfg.max_speed + 1e-7) << deg;
    }
  }
}

TEST(Steer, LargeErrorTurnsInPlace) {
  const DriveConfig cfg;
  WheelSpeeds w = steer(Vec2(0, 8), cfg, false);  // 90 degrees left
  EXPECT_LT(w.left, 0.0f);
  EXPECT_GT(w.right, 0.0f);
  EXPECT_FLOAT_EQ(w.left, -w.right);
  EXPECT_FLOAT_EQ(w.right, static_cast<float>(cfg.hard_turn_speed));
  w = steer(Vec2(-8, -1), cfg, false);  // behind, to the right
  EXPECT_GT(w.left, 0.0f);
  EXPECT_LT(w.right, 0.0f);
  EXPECT_FLOAT_EQ(w.left, -w.right);
}

TEST(Steer, ForcedSoftTurnBeyondTheLimitReversesTheInnerWheel) {
  const DriveConfig cfg;
  WheelSpeeds w = steer(Vec2(0, 1), cfg, true);  // 90 degrees left, 1 cm/s: f = (15 - 90) / 15 = -5
  EXPECT_NEAR(w.left, -0.05, 1e-7);              // 0.01 x -5
  EXPECT_NEAR(w.right, 0.07, 1e-7);              // 0.01 x 7
  w = steer(Vec2(-8, -1), cfg, true);  // behind, to the right: both wheels at the limit, spinning right
  EXPECT_NEAR(w.left, cfg.max_speed, 1e-7);
  EXPECT_NEAR(w.right, -cfg.max_speed, 1e-7);
}

}  // namespace
}  // namespace swarm_forage
