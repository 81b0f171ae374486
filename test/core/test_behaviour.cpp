// How the robots move and forage, measured (docs/FIDELITY.md): FORDYCA's wrapped wander gives
// a lone explorer a persistence length of metres at 6.3 cm/s, carriers move at 8 cm/s, a lone robot
// finds blocks at the rate that search allows, and the nest rules hold.
#include <gtest/gtest.h>

#include <cmath>

#include "swarm_forage/core/controllers/crw.hpp"
#include "swarm_forage/core/run/behaviour_probe.hpp"

namespace swarm_forage {
namespace {

TEST(Behaviour, LoneExplorerWalksNearlyStraightForMetres) {
  const int seeds = 20;
  double path = 0, msd = 0, speed = 0;
  for (int s = 1; s <= seeds; ++s) {
    const PathStats p = loneExplorerPath({}, static_cast<uint32_t>(s), 1000);
    path += p.path / seeds;
    msd += p.net * p.net / seeds;
    speed += p.mean_speed / seeds;
  }
  EXPECT_NEAR(speed, 0.063, 0.0005) << "0.7 x 9 cm/s";
  // bench_behaviour (30 seeds): 7.6 m, rms net 9.9 m over 12.6 m of path; the clamped wander gave 1.77 m.
  const double lp = persistenceLength(msd, path);
  EXPECT_GT(lp, 5.0) << "rms net displacement " << std::sqrt(msd) << " m over " << path << " m";
  EXPECT_LT(lp, 12.0);
}

TEST(Behaviour, PersistenceLengthOfKnownPaths) {
  EXPECT_NEAR(persistenceLength(2 * 1.0 * 100 - 2 * (1 - std::exp(-100.0)), 100), 1.0, 1e-6);
  EXPECT_TRUE(std::isinf(persistenceLength(100, 10)));  // straight
  EXPECT_EQ(persistenceLength(0, 10), 0.0);
}

TEST(Behaviour, LoneRobotDeliversAtTheRateItsSearchAllows) {
  ArenaConfig small;  // 32 x 16, 50 blocks
  double crw = 0;
  for (uint32_t s = 1; s <= 4; ++s) crw += loneDeliveries("crw", small, s, 50000) / 4.0;
  // Measured 4.0 blocks per 10,000 s over seeds 1-10 (2-5; 3.75 over seeds 1-4), 1.4 with the clamped wander.
  EXPECT_GE(crw, 3.0);
  EXPECT_LE(crw, 9.0);
}

TEST(Behaviour, StallTrackerCountsRobotsStandingStillFor50Ticks) {
  StallTracker t(2);
  for (uint64_t k = 0; k < 50; ++k) {
    EXPECT_FALSE(t.stalled(0, 1.0f, 1.0f, k)) << k;              // standing still, not yet 50 ticks
    EXPECT_FALSE(t.stalled(1, 1.0f + 0.02f * k, 1.0f, k)) << k;  // moving 2 cm a tick
  }
  EXPECT_TRUE(t.stalled(0, 1.005f, 1.0f, 50));  // within 1 cm for 50 ticks: stalled
  EXPECT_FALSE(t.stalled(0, 1.02f, 1.0f, 51));  // moved away: the clock restarts
  EXPECT_FALSE(t.stalled(0, 1.02f, 1.0f, 100));
  EXPECT_TRUE(t.stalled(0, 1.02f, 1.0f, 101));
  EXPECT_FALSE(t.stalled(0, 1.02f, 1.0f, 0)) << "a new run (tick 0 again) restarts the clock";
}

/// One CRW robot driven by hand through the delivery states.
TEST(Behaviour, NestRulesWanderWithoutAvoidanceThenStopAndDrop) {
  CrwBatch a(CrwConfig{}, 3, 0, 1), b(CrwConfig{}, 3, 0, 1);
  SensorData s;
  s.resize(1);
  CommandData ca, cb;
  ControllerStatus st;
  // Into transport: on a block after the minimum exploration time, then carrying.
  uint64_t t = 0;
  for (; t < 50; ++t) {
    a.step(t, s, ca, st);
    b.step(t, s, cb, st);
  }
  s.ground[0] = kBlockGround;
  a.step(t, s, ca, st);
  b.step(t++, s, cb, st);
  s.carried_block[0] = 4;
  s.events[0] = kPickupDone;
  s.ground[0] = kFloor;
  s.light_x[0] = 1.0f;
  a.step(t, s, ca, st);
  b.step(t++, s, cb, st);
  ASSERT_EQ(a.state(0), CrwState::kTransport);
  EXPECT_FLOAT_EQ(ca.left[0], 0.08f) << "carriers move at the phototaxis force, 8 cm/s";
  EXPECT_FLOAT_EQ(ca.right[0], 0.08f);
  s.events[0] = 0;
  s.ground[0] = kNest;
  // In the nest: 25 ticks of wander; an obstacle changes nothing (no avoidance), and no 0.7 scaling.
  SensorData threatened = s;
  threatened.threatened[0] = 1;
  threatened.obstacle_x[0] = 0.05f;
  for (int k = 0; k < 25; ++k, ++t) {
    a.step(t, s, ca, st);
    b.step(t, threatened, cb, st);
    ASSERT_EQ(a.state(0), CrwState::kNestWander) << k;
    ASSERT_EQ(ca.left[0], cb.left[0]) << k;
    ASSERT_EQ(ca.right[0], cb.right[0]) << k;
    ASSERT_GT(ca.left[0] + ca.right[0], 0.14f) << "wander force 9 cm/s (x 0.7 would be at most 0.126)";
  }
  a.step(t++, s, ca, st);
  EXPECT_EQ(a.state(0), CrwState::kDrop);
  EXPECT_EQ(ca.left[0], 0.0f);
  EXPECT_EQ(ca.right[0], 0.0f);
  EXPECT_EQ(ca.request[0], kDrop);
  s.carried_block[0] = -1;
  s.events[0] = kDropDone;
  a.step(t++, s, ca, st);
  EXPECT_EQ(a.state(0), CrwState::kLeaveNest);
  EXPECT_GT(ca.left[0] + ca.right[0], 0.14f) << "leaving the nest: wander at full force";
}

}  // namespace
}  // namespace swarm_forage
