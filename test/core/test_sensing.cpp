// World::sense on hand-built scenes (robots placed with World::setPose).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "sharing_pool.hpp"
#include "swarm_forage/core/util/simd.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {
namespace {

constexpr double kR = 0.085;  // RobotConfig default radius

/// A world of n robots, all parked far apart in the middle of the 32 x 16 arena (away from the
/// nest, the source and the walls); tests then move the robots they need.
World makeWorld(uint32_t n) {
  WorldConfig c;
  c.n_robots = n;
  c.seed = 1;
  World w(c);
  for (uint32_t i = 0; i < n; ++i) w.setPose(i, 10.0 + 2.0 * i, 4.0, 0.0);
  return w;
}

SensorData senseAll(World& w) {
  SensorData s;
  w.sense(s);
  return s;
}

/// Angle [deg] of the threatening obstacle in the robot frame.
double obstacleDeg(const SensorData& s, int i) {
  return std::atan2(s.obstacle_y[i], s.obstacle_x[i]) * 180 / kPi;
}

// The obstacle is what the first of the foot-bot's proximity rays (sensor k at 7.5 + 15k degrees,
// counter-clockwise from the front) sees within 0.1 m of the body, as FORDYCA's closest_prox_obj reads it.
TEST(Sensing, WallAheadIsSeenByTheFirstRay) {
  World w = makeWorld(1);
  const double gap = 0.05;
  w.setPose(0, kR + gap, 8.0, kPi);  // left wall 0.05 m from the body, facing it
  SensorData s = senseAll(w);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s.threatened[0], 1);
  // Sensor 0, 7.5 degrees left of the heading, as far along it as the wall is.
  EXPECT_NEAR(obstacleDeg(s, 0), 7.5, 1e-4);
  EXPECT_NEAR(std::hypot(s.obstacle_x[0], s.obstacle_y[0]), (kR + gap) / std::cos(deg2rad(7.5)), 1e-6);

  // The same wall 60 degrees to the robot's left: sensor 0's ray is too slanted to reach it, sensor 1's
  // (22.5 degrees) is the first that does.
  w.setPose(0, kR + gap, 8.0, kPi - deg2rad(60));
  s = senseAll(w);
  EXPECT_EQ(s.threatened[0], 1);
  EXPECT_NEAR(obstacleDeg(s, 0), 22.5, 1e-4);

  // The top wall, ahead of a robot heading +y.
  w.setPose(0, 16.0, 16.0 - kR - gap, kPi / 2);
  s = senseAll(w);
  EXPECT_EQ(s.threatened[0], 1);
  EXPECT_NEAR(obstacleDeg(s, 0), 7.5, 1e-4);
}

TEST(Sensing, WallOutsideFieldOfViewDoesNotThreaten) {
  World w = makeWorld(1);
  w.setPose(0, kR + 0.08, 8.0, 0.0);  // wall straight behind, 8 cm away: no ray within +-150 reaches it
  SensorData s = senseAll(w);
  EXPECT_EQ(s.threatened[0], 0);
  EXPECT_FLOAT_EQ(s.obstacle_x[0], 0.0f);
  EXPECT_FLOAT_EQ(s.obstacle_y[0], 0.0f);
  w.setPose(0, kR + 0.08, 8.0, kPi - deg2rad(175));  // 175 degrees off the heading
  EXPECT_EQ(senseAll(w).threatened[0], 0);
  w.setPose(0, kR + 0.08, 8.0, kPi - deg2rad(140));  // 140 degrees: sensors 8 and 9 reach it, 8 first
  s = senseAll(w);
  EXPECT_EQ(s.threatened[0], 1);
  EXPECT_NEAR(obstacleDeg(s, 0), 127.5, 1e-4);
  // 5 cm straight behind, the rear rays at 142.5 degrees do reach the wall.
  w.setPose(0, kR + 0.05, 8.0, 0.0);
  s = senseAll(w);
  EXPECT_EQ(s.threatened[0], 1);
  EXPECT_NEAR(obstacleDeg(s, 0), 142.5, 1e-4);
}

TEST(Sensing, WallBeyondThreatDistanceDoesNotThreaten) {
  World w = makeWorld(1);
  w.setPose(0, kR + 0.15, 8.0, kPi);
  EXPECT_EQ(senseAll(w).threatened[0], 0);
}

TEST(Sensing, RobotsFaceToFaceBothSeeTheOtherFrontLeft) {
  World w = makeWorld(2);
  const double gap = 0.05;
  w.setPose(0, 10.0, 8.0, 0.0);
  w.setPose(1, 10.0 + 2 * kR + gap, 8.0, kPi);
  ASSERT_TRUE(w.overlapFree());
  SensorData s = senseAll(w);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(s.threatened[i], 1) << "robot " << i;
    // Sensor 0 (front left) sees the other body first: both dodge to their right and pass.
    EXPECT_NEAR(obstacleDeg(s, i), 7.5, 1e-4) << "robot " << i;
    EXPECT_GT(std::hypot(s.obstacle_x[i], s.obstacle_y[i]), kR + gap - 1e-6) << "robot " << i;
  }

  w.setPose(1, 10.0 + 2 * kR + 0.2, 8.0, kPi);
  s = senseAll(w);
  EXPECT_EQ(s.threatened[0], 0);
  EXPECT_EQ(s.threatened[1], 0);

  // Back to back at 0.05 m: outside each other's field of view.
  w.setPose(0, 10.0, 8.0, kPi);
  w.setPose(1, 10.0 + 2 * kR + gap, 8.0, 0.0);
  s = senseAll(w);
  EXPECT_EQ(s.threatened[0], 0);
  EXPECT_EQ(s.threatened[1], 0);
}

TEST(Sensing, SensorOrderNotDistanceDecides) {
  World w = makeWorld(3);
  // Robot 1 close on the right front (-30 degrees, 2 cm gap), robot 2 further on the left (90 degrees,
  // 8 cm gap): the left one is reported, as FORDYCA does (left sensors come first in ARGoS' order).
  w.setPose(0, 10.0, 8.0, 0.0);
  const double d1 = 2 * kR + 0.02, d2 = 2 * kR + 0.08;
  w.setPose(1, 10.0 + d1 * std::cos(deg2rad(-30)), 8.0 + d1 * std::sin(deg2rad(-30)), 0.0);
  w.setPose(2, 10.0, 8.0 + d2, 0.0);
  ASSERT_TRUE(w.overlapFree());
  SensorData s = senseAll(w);
  EXPECT_EQ(s.threatened[0], 1);
  EXPECT_NEAR(obstacleDeg(s, 0), 82.5, 1e-4);
  // Without robot 2 the right one is seen, by the first right-side ray that reaches it.
  w.setPose(2, 20.0, 8.0, 0.0);
  s = senseAll(w);
  EXPECT_EQ(s.threatened[0], 1);
  EXPECT_LT(obstacleDeg(s, 0), 0.0);
}

TEST(Sensing, LightPointsToTheNest) {
  World w = makeWorld(1);
  w.setPose(0, 16.0, 8.0, 0.0);  // nest lights at x = 3.2: facing away from them
  SensorData s = senseAll(w);
  EXPECT_LT(s.light_x[0], 0.0f);
  EXPECT_NEAR(s.light_y[0], 0.0, 1e-6);                           // lights symmetric about y = 8
  EXPECT_NEAR(std::hypot(s.light_x[0], s.light_y[0]), 3.0, 0.1);  // three nearly parallel units

  w.setPose(0, 16.0, 8.0, kPi);  // facing the nest
  s = senseAll(w);
  EXPECT_GT(s.light_x[0], 0.0f);

  w.setPose(0, 16.0, 8.0, kPi / 2);  // nest on the robot's left
  s = senseAll(w);
  EXPECT_GT(s.light_y[0], 0.0f);
  EXPECT_NEAR(s.light_x[0], 0.0, 1e-6);
}

TEST(Sensing, GroundReadings) {
  World w = makeWorld(1);
  const ArenaConfig& arena = w.config().arena;
  const Rect nest = arena.nest();
  w.setPose(0, (nest.min_x + nest.max_x) / 2, (nest.min_y + nest.max_y) / 2, 0.0);
  EXPECT_EQ(senseAll(w).ground[0], kNest);
  w.setPose(0, nest.min_x + 0.01, nest.max_y - 0.01, 0.0);
  EXPECT_EQ(senseAll(w).ground[0], kNest);
  w.setPose(0, nest.max_x + 0.01, 8.0, 0.0);
  EXPECT_EQ(senseAll(w).ground[0], kFloor);

  const BlockField& blocks = w.blocks();
  for (int32_t b : {0, 1}) {  // a cube and a ramp
    const Rect f = blocks.footprint(b);
    w.setPose(0, blocks.x(b), blocks.y(b), 0.0);
    EXPECT_EQ(senseAll(w).ground[0], kBlockGround) << "block " << b;
    w.setPose(0, f.max_x - 0.01, f.min_y + 0.01, 0.0);
    EXPECT_EQ(senseAll(w).ground[0], kBlockGround) << "block " << b;
  }
  EXPECT_EQ(blocks.kind(1), kRamp);

  w.setPose(0, 16.0, 8.0, 0.0);
  EXPECT_EQ(senseAll(w).ground[0], kFloor);
  w.setPose(0, 0.5 * (arena.source().min_x + 16.0), 8.0, 0.0);
  EXPECT_EQ(senseAll(w).ground[0], kFloor);
}

TEST(Sensing, PoseIsReported) {
  World w = makeWorld(2);
  w.setPose(1, 12.5, 7.25, 0.5);
  const SensorData s = senseAll(w);
  EXPECT_FLOAT_EQ(s.x[1], 12.5f);
  EXPECT_FLOAT_EQ(s.y[1], 7.25f);
  EXPECT_FLOAT_EQ(s.theta[1], 0.5f);
  EXPECT_EQ(s.carried_block[1], -1);
  EXPECT_EQ(s.events[1], 0);
}

TEST(Sensing, PickupEventAfterSuccessfulRequest) {
  World w = makeWorld(2);
  w.setPose(0, w.blocks().x(3), w.blocks().y(3), 0.0);
  SensorData s = senseAll(w);
  ASSERT_EQ(s.ground[0], kBlockGround);
  EXPECT_EQ(s.events[0], 0);
  EXPECT_EQ(s.carried_block[0], -1);

  CommandData c;
  c.resize(2);
  c.request[0] = kPickup;
  c.request[1] = kPickup;  // robot 1 stands on the floor: nothing to pick up
  w.step(c, 0.0);
  s = senseAll(w);
  EXPECT_TRUE(s.events[0] & kPickupDone);
  EXPECT_EQ(s.carried_block[0], 3);
  EXPECT_EQ(s.ground[0], kFloor);          // the block is no longer on the floor
  EXPECT_EQ(s.events[1], kBlockVanished);  // a failed pick-up tells DPO its memory is stale
  EXPECT_EQ(s.carried_block[1], -1);

  // Events describe the last step only.
  c.request[0] = kNone;
  w.step(c, 0.0);
  s = senseAll(w);
  EXPECT_EQ(s.events[0], 0);
  EXPECT_EQ(s.carried_block[0], 3);

  // Drop (outside the nest): kDropDone, nothing carried.
  c.request[0] = kDrop;
  w.step(c, 0.0);
  s = senseAll(w);
  EXPECT_TRUE(s.events[0] & kDropDone);
  EXPECT_EQ(s.carried_block[0], -1);
}

/// A world of 480 robots packed into two corners of the 32 x 16 arena (walls on every side of some,
/// eight or more neighbours within reach of most), some of them out of the swarm.
World crowdedWorld(bool occlusion) {
  WorldConfig c;
  c.n_robots = 480;
  c.seed = 3;
  c.population.death = 0.3;
  c.population.malfunction = 0.3;
  c.population.repair = 0.1;
  if (occlusion) c.quirks.set(Quirk::kLightOcclusion);
  World w(c);
  uint32_t h = 12345;
  const auto next = [&h] {  // a small LCG: jitter and headings
    h = h * 1664525u + 1013904223u;
    return (h >> 8) / double(1u << 24);
  };
  const double pitch = 2 * kR + 0.012;
  for (uint32_t i = 0; i < c.n_robots; ++i) {
    const uint32_t k = i % 240, col = k % 16, row = k / 16;
    const double jx = 0.005 * next(), jy = 0.005 * next(), th = 20 * (next() - 0.5);
    if (i < 240)
      w.setPose(i, kR + 0.001 + col * pitch + jx, kR + 0.001 + row * pitch + jy, th);
    else
      w.setPose(i, 32.0 - kR - 0.007 - col * pitch + jx, 16.0 - kR - 0.007 - row * pitch + jy, th);
  }
  return w;
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// The 4-lane path of sensing_x4.cpp does the scalar path's arithmetic: the same readings, bit for bit,
// tick after tick (nearest2_ too: the motion it gates is compared as well).
TEST(Sensing, FourLanePathReadsTheSameBits) {
  const bool was = simdEnabled();
  setSimdEnabled(true);
  if (!simdEnabled()) {
    setSimdEnabled(was);
    GTEST_SKIP() << "no AVX2 here";
  }
  for (const bool occlusion : {false, true}) {
    World scalar = crowdedWorld(occlusion), lanes = crowdedWorld(occlusion);
    CommandData c;
    c.resize(480);
    for (uint32_t i = 0; i < 480; ++i) {
      c.left[i] = 0.1f * static_cast<float>(i % 3);
      c.right[i] = 0.1f * static_cast<float>((i / 3) % 3);
    }
    int threatened = 0, inactive = 0;
    for (int t = 0; t < 40; ++t) {
      SensorData a, b;
      setSimdEnabled(false);
      scalar.sense(a);
      scalar.step(c, 0.0);
      setSimdEnabled(true);
      lanes.sense(b);
      lanes.step(c, 0.0);
      ASSERT_TRUE(sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.theta, b.theta)) << "tick " << t;
      ASSERT_TRUE(sameBits(a.threatened, b.threatened)) << "tick " << t;
      ASSERT_TRUE(sameBits(a.obstacle_x, b.obstacle_x) && sameBits(a.obstacle_y, b.obstacle_y))
          << "tick " << t;
      ASSERT_TRUE(sameBits(a.light_x, b.light_x) && sameBits(a.light_y, b.light_y)) << "tick " << t;
      ASSERT_TRUE(sameBits(a.ground, b.ground) && sameBits(a.active, b.active)) << "tick " << t;
      ASSERT_TRUE(sameBits(scalar.shadowMasks(), lanes.shadowMasks())) << "tick " << t;
      ASSERT_TRUE(sameBits(scalar.robots().x, lanes.robots().x) &&
                  sameBits(scalar.robots().y, lanes.robots().y))
          << "tick " << t;
      for (std::size_t i = 0; i < a.size(); ++i) {
        threatened += a.threatened[i];
        inactive += !a.isActive(i);
      }
    }
    EXPECT_GT(threatened, 40 * 100);  // the crowd was sensed, not an empty arena
    EXPECT_GT(inactive, 0);
  }
  setSimdEnabled(was);
}

// With a stale grid, sense() reads what needs no grid (pose, ground, lights) by id while one thread builds
// the grid; with a fresh one (sensed twice in a tick), after it. Both give the same bits, on 1 or 2
// threads; a robot out of the swarm reads no light and the floor, and one in it the lights' unit vectors
// turned into its frame.
TEST(Sensing, ReadingsByIdAreTheSameWhetherTheGridIsBuiltBesideThemOrNot) {
  for (const bool occlusion : {false, true}) {
    for (const unsigned threads : {1u, 2u}) {
      World w = crowdedWorld(occlusion);
      w.setPool(sharingPool(threads));
      CommandData c;
      c.resize(480);
      for (uint32_t i = 0; i < 480; ++i) c.left[i] = c.right[i] = 0.05f;
      for (int t = 0; t < 5; ++t) {
        SensorData s;
        w.sense(s);
        w.step(c, 0.0);
      }
      SensorData a, b;
      w.sense(a);  // the grid is stale after a step
      w.sense(b);
      ASSERT_TRUE(sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.theta, b.theta));
      ASSERT_TRUE(sameBits(a.light_x, b.light_x) && sameBits(a.light_y, b.light_y));
      ASSERT_TRUE(sameBits(a.ground, b.ground) && sameBits(a.events, b.events));
      ASSERT_TRUE(sameBits(a.carried_block, b.carried_block) && sameBits(a.threatened, b.threatened));
      ASSERT_TRUE(sameBits(a.obstacle_x, b.obstacle_x) && sameBits(a.obstacle_y, b.obstacle_y));
      int inactive = 0;
      for (std::size_t i = 0; i < a.size(); ++i) {
        if (a.isActive(i)) continue;
        ++inactive;
        EXPECT_EQ(a.light_x[i], 0.0f);
        EXPECT_EQ(a.light_y[i], 0.0f);
        EXPECT_EQ(a.ground[i], kFloor);
      }
      EXPECT_GT(inactive, 0);
      if (occlusion) continue;
      const uint32_t i = 7;  // active in this world: its reading against the definition
      ASSERT_TRUE(a.isActive(i));
      const double x = w.robots().x[i], y = w.robots().y[i], th = w.robots().theta[i];
      double lx = 0, ly = 0;
      for (int l = 0; l < ArenaConfig::kLights; ++l) {
        const Vec2 p = w.config().arena.light(l);
        const double d = std::hypot(p.x() - x, p.y() - y);
        lx += (p.x() - x) / d;
        ly += (p.y() - y) / d;
      }
      EXPECT_NEAR(a.light_x[i], std::cos(th) * lx + std::sin(th) * ly, 1e-5);
      EXPECT_NEAR(a.light_y[i], -std::sin(th) * lx + std::cos(th) * ly, 1e-5);
    }
  }
}

}  // namespace
}  // namespace swarm_forage
