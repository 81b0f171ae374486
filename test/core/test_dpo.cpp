// DPO controller: pheromone store, utility selection, vectoring, collision recovery, split
// invariance, parameter validation; and the controller factory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "config_checks.hpp"
#include "sensor_readings.hpp"
#include "swarm_forage/core/controllers/block_memory.hpp"
#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/controllers/dpo.hpp"
#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {
namespace {

struct Seen {
  int32_t id;
  float x, y;
};

/// Fills the flattened line of sight of every robot with the blocks lying in its LineOfSight rect.
void see(SensorData& s, std::vector<Seen> blocks) {
  std::sort(blocks.begin(), blocks.end(), [](const Seen& a, const Seen& b) { return a.id < b.id; });
  s.clearLineOfSight();
  s.los_block_offset.push_back(0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Rect r = LineOfSight{}.around(s.x[i], s.y[i]);
    for (const Seen& b : blocks) {
      if (!r.contains(b.x, b.y)) continue;
      s.los_block_id.push_back(b.id);
      s.los_block_x.push_back(b.x);
      s.los_block_y.push_back(b.y);
    }
    s.los_block_offset.push_back(static_cast<uint32_t>(s.los_block_id.size()));
  }
}

/// One DPO robot in a hand-built world of blocks.
class DpoOne : public ::testing::Test {
 protected:
  DpoOne() : dpo_(DpoConfig{}, 9, 0, 1) { s_.resize(1); }
  void place(float x, float y, float theta = 0.f) {
    s_.x[0] = x;
    s_.y[0] = y;
    s_.theta[0] = theta;
  }
  DpoState step() {
    see(s_, world_);
    dpo_.step(tick_++, s_, cmd_, status_);
    return dpo_.state(0);
  }
  double rho(int32_t id) const {
    const Remembered* r = dpo_.blocks().find(0, id);
    return r != nullptr ? r->rho : -1.0;
  }

  DpoBatch dpo_;
  SensorData s_;
  std::vector<Seen> world_;
  CommandData cmd_;
  ControllerStatus status_;
  uint64_t tick_ = 0;
};

TEST_F(DpoOne, PheromoneCreationDecayAndNewPlace) {
  place(1.1f, 1.1f);
  world_ = {{7, 1.4f, 1.1f}};
  EXPECT_EQ(step(), DpoState::kVector);
  EXPECT_EQ(rho(7), 1.0);  // first seen
  EXPECT_EQ(dpo_.target(0), 7);
  for (int k = 1; k <= 1000; ++k) step();  // seen again at the same place: no reset
  EXPECT_NEAR(rho(7), std::pow(1.0 - 1e-5, 1000), 1e-14);
  world_[0].y = 1.3f;  // seen at a new place
  step();
  EXPECT_EQ(rho(7), 1.0);
  EXPECT_FLOAT_EQ(dpo_.blocks().find(0, 7)->y, 1.3f);
  step();
  EXPECT_DOUBLE_EQ(rho(7), 1.0 - 1e-5);
}

TEST_F(DpoOne, ForgetsWhenInSightAndGoneButNotOutOfSight) {
  place(1.1f, 1.1f);
  world_ = {{7, 1.4f, 1.1f}, {8, 1.1f, 1.5f}};
  step();
  ASSERT_EQ(dpo_.blocks().size(0), 2u);
  place(5.0f, 5.0f);  // both out of sight: gone from the world, still remembered
  world_.clear();
  step();
  EXPECT_EQ(dpo_.blocks().size(0), 2u);
  place(1.1f, 1.1f);  // back in sight: both missing, forgotten
  EXPECT_EQ(step(), DpoState::kExplore);
  EXPECT_EQ(dpo_.blocks().size(0), 0u);
  EXPECT_EQ(dpo_.target(0), -1);
}

TEST_F(DpoOne, RemovedOnPickupAndCarriedBlockIgnored) {
  place(1.1f, 1.1f);
  world_ = {{7, 1.4f, 1.1f}, {9, 1.1f, 1.55f}};
  ASSERT_EQ(step(), DpoState::kVector);
  ASSERT_EQ(dpo_.target(0), 7);  // U = 7.13 / 0.3 = 23.8 against 6.78 / 0.45 = 15.1
  place(1.39f, 1.1f);
  s_.ground[0] = kBlockGround;
  EXPECT_EQ(step(), DpoState::kPickup);
  EXPECT_EQ(cmd_.request[0], kPickup);
  EXPECT_EQ(cmd_.left[0], 0.0f);
  s_.events[0] = kPickupDone;
  s_.carried_block[0] = 7;
  world_[0] = {7, 1.39f, 1.1f};  // reported under the robot while carried: ignored
  EXPECT_EQ(step(), DpoState::kTransport);
  EXPECT_EQ(dpo_.blocks().find(0, 7), nullptr);
  EXPECT_NE(dpo_.blocks().find(0, 9), nullptr);
  s_.events[0] = 0;
  step();
  EXPECT_EQ(dpo_.blocks().find(0, 7), nullptr);
}

TEST_F(DpoOne, FailedPickupForgetsTheTarget) {
  place(1.1f, 1.1f);
  world_ = {{7, 1.4f, 1.1f}};
  step();
  place(1.39f, 1.1f);
  s_.ground[0] = kBlockGround;
  ASSERT_EQ(step(), DpoState::kPickup);
  s_.events[0] = kBlockVanished;  // someone else was faster
  EXPECT_EQ(step(), DpoState::kExplore);
  EXPECT_EQ(dpo_.blocks().find(0, 7), nullptr);
}

TEST(DpoUtility, HandComputedAndArgmaxWithExclusion) {
  const Vec2 nest(3.2, 8.0), robot(10, 4);
  // P (10, 8): |P - nest| = 6.8, |P - robot| = 4: U = 1.7 e^1 = 4.62108.
  EXPECT_NEAR(objectUtility(Vec2(10, 8), robot, nest, 1.0), 1.7 * std::exp(1.0), 1e-12);
  // Q (6, 4): sqrt(2.8^2 + 4^2) / 4 = 1.22066, x e^2 = 9.0196: more pheromone beats a better ratio.
  // R (10, 4.1): sqrt(6.8^2 + 3.9^2) / 0.1 = 78.4 x e^0: the largest, but within 0.2 m of the robot.
  const std::vector<Remembered> e = {{1, 10, 8, 1.0}, {2, 6, 4, 2.0}, {3, 10, 4.1f, 0.0}};
  EXPECT_NEAR(objectUtility(Vec2(6, 4), robot, nest, 2.0), std::hypot(2.8, 4.0) / 4 * std::exp(2.0), 1e-12);
  EXPECT_EQ(bestByUtility(e, robot, nest, 0.2), 1);
  EXPECT_EQ(bestByUtility(e, robot, nest, 0.05), 2);
  EXPECT_EQ(bestByUtility(e, robot, nest, 100.0), -1);
  EXPECT_EQ(bestByUtility({}, robot, nest, 0.2), -1);
}

TEST_F(DpoOne, SelectsTheBestBlockOutsideTheExclusionRadius) {
  place(1.1f, 1.1f);
  // U_A = 7.2 / 0.1 (excluded); U_B = |(1.55,1.1)-nest| / 0.45 = 15.77; U_C = |(1.1,1.45)-nest| / 0.35
  // = 19.65.
  world_ = {{3, 1.2f, 1.1f}, {5, 1.55f, 1.1f}, {9, 1.1f, 1.45f}};
  EXPECT_EQ(step(), DpoState::kVector);
  EXPECT_EQ(dpo_.target(0), 9);
  world_ = {{3, 1.2f, 1.1f}};  // only the excluded one left: explore
  EXPECT_EQ(step(), DpoState::kExplore);
  EXPECT_EQ(dpo_.target(0), -1);
}

TEST_F(DpoOne, VectoringSlowsInsideTheSlowingRadiusIgnoringObstaclesAndArrives) {
  place(4.45f, 5.05f);
  world_ = {{4, 4.95f, 5.05f}};
  ASSERT_EQ(step(), DpoState::kVector);
  EXPECT_FLOAT_EQ(cmd_.left[0], 0.08f);  // 8 cm/s straight ahead (FORDYCA's arrival max)
  EXPECT_FLOAT_EQ(cmd_.right[0], 0.08f);
  s_.threatened[0] = 1;  // an obstacle ahead-left ...
  s_.obstacle_x[0] = s_.obstacle_y[0] = 0.05f;
  place(4.85f, 5.05f);  // ... 0.1 m from the block: half the force, the obstacle is ignored
  step();
  EXPECT_NEAR(cmd_.left[0], 0.04, 1e-5);
  EXPECT_NEAR(cmd_.right[0], 0.04, 1e-5);
  EXPECT_FALSE(dpo_.avoiding(0));
  place(4.928f, 5.05f);  // 0.022 m: 8 x 0.022 / 0.2 < 1: the force never falls below slowing_speed_min
  step();
  EXPECT_NEAR(cmd_.left[0], 0.01, 1e-5);
  place(4.45f, 5.05f);  // outside the slowing radius the same obstacle is avoided (a hard turn right)
  step();
  EXPECT_TRUE(dpo_.avoiding(0));
  EXPECT_FLOAT_EQ(cmd_.left[0], 0.1f);
  EXPECT_FLOAT_EQ(cmd_.right[0], -0.1f);
  EXPECT_EQ(cmd_.request[0], kNone);
  place(4.935f, 5.05f);  // within 0.02 m, on the block
  s_.ground[0] = kBlockGround;
  EXPECT_EQ(step(), DpoState::kPickup);
  EXPECT_EQ(cmd_.request[0], kPickup);
  EXPECT_EQ(cmd_.task[0], kTaskNone);  // DPO robots have no task to show
}

TEST_F(DpoOne, ArrivesFromManyPosesWithDifferentialDriveKinematics) {
  const Vec2 block(3.1, 3.1);
  for (double start = 0; start < 2 * kPi; start += kPi / 5) {
    for (double heading : {0.0, 2.0, -2.5}) {
      DpoBatch dpo(DpoConfig{}, 3, 0, 1);
      double x = block.x() + 0.45 * std::cos(start), y = block.y() + 0.45 * std::sin(start), th = heading;
      bool arrived = false;
      for (uint64_t t = 0; t < 400 && !arrived; ++t) {
        place(static_cast<float>(x), static_cast<float>(y), static_cast<float>(th));
        s_.ground[0] = std::hypot(x - block.x(), y - block.y()) < 0.1 ? kBlockGround : kFloor;
        see(s_, {{1, 3.1f, 3.1f}});
        dpo.step(t, s_, cmd_, status_);
        arrived = cmd_.request[0] == kPickup;
        const double v = (cmd_.left[0] + cmd_.right[0]) / 2, w = (cmd_.right[0] - cmd_.left[0]) / 0.14;
        x += v * std::cos(th) * 0.2;
        y += v * std::sin(th) * 0.2;
        th += w * 0.2;
      }
      EXPECT_TRUE(arrived) << "start angle " << start << " heading " << heading;
      EXPECT_LE(std::hypot(x - block.x(), y - block.y()), 0.02 + 1e-6);
    }
  }
}

TEST_F(DpoOne, SecondCollisionWithinWindowTurnsToANewDirection) {
  place(2.1f, 2.1f);
  world_ = {{1, 2.55f, 2.1f}};
  ASSERT_EQ(step(), DpoState::kVector);  // tick 0
  s_.threatened[0] = 1;                  // tick 1: a first collision (obstacle ahead): avoidance alone
  s_.obstacle_x[0] = 0.08f;
  step();
  EXPECT_TRUE(dpo_.avoiding(0));
  EXPECT_FLOAT_EQ(std::fabs(cmd_.left[0]), 0.1f);  // the avoidance force points behind: a hard turn
  EXPECT_FLOAT_EQ(cmd_.right[0], -cmd_.left[0]);
  s_.threatened[0] = 0;  // tick 2: the episode ends; 10 ticks straight at 0.7 vmax, then vectoring
  for (int k = 0; k < 10; ++k) {
    step();
    ASSERT_TRUE(dpo_.recovering(0)) << k;
    ASSERT_FLOAT_EQ(cmd_.left[0], 0.07f) << k;
    ASSERT_FLOAT_EQ(cmd_.right[0], 0.07f) << k;
  }
  step();
  EXPECT_FALSE(dpo_.recovering(0));
  EXPECT_FLOAT_EQ(cmd_.left[0], 0.08f);
  while (tick_ < 50) step();
  s_.threatened[0] = 1;  // tick 50: 48 ticks after the last episode ended: a new direction
  step();
  s_.threatened[0] = 0;
  int spin = 0;  // spinning in place at the hard-turn speed toward U[0, 1] rad left of the heading
  while (cmd_.left[0] == -0.1f && cmd_.right[0] == 0.1f) {
    ++spin;
    step();
  }
  // The heading never changes here, so the spin lasts 10 ticks unless the draw fell within 0.25 rad.
  EXPECT_TRUE(spin == 10 || spin == 0) << spin;
  int straight = 0;  // then 10 ticks straight at 0.7 vmax
  while (cmd_.left[0] == 0.07f && cmd_.right[0] == 0.07f) {
    ++straight;
    step();
  }
  EXPECT_EQ(straight, 10);
  EXPECT_FALSE(dpo_.recovering(0));
  while (tick_ < 400) step();  // the next collision comes > 300 ticks after the last episode
  s_.threatened[0] = 1;
  step();
  EXPECT_TRUE(dpo_.avoiding(0));
  EXPECT_FALSE(dpo_.recovering(0));
}

TEST(DpoMemory, BoundedSortedAndMergedCorrectly) {
  ObjectMemory m(1);
  const PheromoneModel model;
  const Rect nowhere{0, 0, 0, 0};
  std::vector<int32_t> ids;
  std::vector<float> xs, ys;
  for (uint64_t t = 0; t < 1000; ++t) {  // random subsets of 20 ids at random places
    ids.clear();
    xs.clear();
    ys.clear();
    for (int32_t id = 0; id < 20; ++id) {
      const uint64_t h = mix64(t * 131 + static_cast<uint64_t>(id));
      if (h % 4 != 0) continue;
      ids.push_back(id);
      xs.push_back(static_cast<float>((h >> 8) % 100) * 0.1f);
      ys.push_back(static_cast<float>((h >> 16) % 100) * 0.1f);
    }
    m.update(0, model, nowhere, ids.data(), xs.data(), ys.data(), static_cast<uint32_t>(ids.size()), -1);
    ASSERT_LE(m.size(0), 20u);
    for (std::size_t k = 1; k < m.size(0); ++k) ASSERT_LT(m.of(0)[k - 1].id, m.of(0)[k].id);
  }
  EXPECT_EQ(m.size(0), 20u);
  EXPECT_FALSE(m.forget(0, 77));
  EXPECT_TRUE(m.forget(0, 3));
  EXPECT_EQ(m.find(0, 3), nullptr);
}

TEST(DpoMemory, CertainSightIsRobustToCellBoundaries) {
  const LineOfSight los;
  const Rect inside = certainSight(los, 1.1, 1.1);  // cell 5: [0.6, 1.6] less 1 mm
  EXPECT_NEAR(inside.min_x, 0.601, 1e-9);
  EXPECT_NEAR(inside.max_y, 1.599, 1e-9);
  const Rect edge = certainSight(los, 1.0, 1.1);  // x on a cell boundary: [0.6, 1.4] less 1 mm
  EXPECT_NEAR(edge.min_x, 0.601, 1e-9);
  EXPECT_NEAR(edge.max_x, 1.399, 1e-9);
}

/// Varied readings with line of sight: one block per robot (present 2/3 of the time, moved every 150
/// ticks) and, in 40-tick windows, the robot on it, near it on the floor, near it in the nest, or on
/// another block, so that every state is reached.
void fillSensors(SensorData& s, std::size_t n, uint64_t t) {
  s.resize(n);
  std::vector<Seen> blocks;
  for (std::size_t i = 0; i < n; ++i) {
    const uint64_t h = mix64(i * 1000003u + t), w = mix64(i * 7919u + t / 40 + 0x5bd1e995u);
    const uint64_t e = mix64(i * 31u + (t / 150) * 1009u);
    const bool present = e % 3 != 0;
    const float bx = 2.1f + static_cast<float>(i % 6) * 3.0f + static_cast<float>((e >> 8) % 5) * 0.1f;
    const float by = 2.1f + static_cast<float>(i / 6) * 3.0f + static_cast<float>((e >> 16) % 5) * 0.1f;
    if (present) blocks.push_back({static_cast<int32_t>(i), bx, by});
    const uint64_t mode = (w >> 30) % 4;
    s.x[i] = mode == 0 ? bx : bx - 0.35f;
    s.y[i] = by;
    s.theta[i] = static_cast<float>((h >> 56) % 60) * 0.1f - 3.0f;
    s.ground[i] = mode == 0 ? (present ? kBlockGround : kFloor)
                            : (mode == 1 ? kFloor : (mode == 2 ? kNest : kBlockGround));
    fillVariedReadings(s, i, h, w);
  }
  see(s, blocks);
}

bool sameCommands(const CommandData& a, const CommandData& b) {
  return a.size() == b.size() && std::memcmp(a.left.data(), b.left.data(), a.size() * sizeof(float)) == 0 &&
         std::memcmp(a.right.data(), b.right.data(), a.size() * sizeof(float)) == 0 && a.request == b.request;
}

TEST(Dpo, SplitInvarianceAndStatus) {
  const uint32_t n = 24, half = 10;  // uneven split on purpose
  DpoBatch whole(DpoConfig{}, 77, 0, n), lo(DpoConfig{}, 77, 0, half), hi(DpoConfig{}, 77, half, n - half);
  SensorData s;
  CommandData cw, cl, ch;
  ControllerStatus sw, sl, sh;
  std::vector<bool> seen(static_cast<std::size_t>(DpoState::kCount), false);
  bool recovered = false;
  for (uint64_t t = 0; t < 1000; ++t) {
    fillSensors(s, n, t);
    whole.step(t, s, cw, sw);
    lo.step(t, s, cl, sl);
    hi.step(t, s, ch, sh);
    ASSERT_EQ(ch.first_id, half);
    CommandData joined;
    joined.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
      const CommandData& part = i < half ? cl : ch;
      const DpoBatch& b = i < half ? lo : hi;
      const uint32_t l = i < half ? i : i - half;
      joined.left[i] = part.left[l];
      joined.right[i] = part.right[l];
      joined.request[i] = part.request[l];
      ASSERT_EQ(whole.state(i), b.state(l)) << "robot " << i << " tick " << t;
      ASSERT_EQ(whole.blocks().size(i), b.blocks().size(l));
      seen[static_cast<std::size_t>(whole.state(i))] = true;
      recovered = recovered || whole.recovering(i);
    }
    ASSERT_TRUE(sameCommands(cw, joined)) << "tick " << t;
    ASSERT_EQ(sw.in_avoidance, sl.in_avoidance + sh.in_avoidance);
    ASSERT_EQ(sw.stalled, sl.stalled + sh.stalled);
    ASSERT_EQ(sw.state_names.size(), static_cast<std::size_t>(DpoState::kCount));
    ASSERT_EQ(std::accumulate(sw.state_counts.begin(), sw.state_counts.end(), 0u), n);
    for (std::size_t k = 0; k < sw.state_counts.size(); ++k)
      ASSERT_EQ(sw.state_counts[k], sl.state_counts[k] + sh.state_counts[k]);
  }
  for (std::size_t k = 0; k < seen.size(); ++k)
    EXPECT_TRUE(seen[k]) << dpoStateName(static_cast<DpoState>(k));
  EXPECT_TRUE(recovered);
  EXPECT_EQ(sw.state_names[1], "vector");
}

TEST(Dpo, ValidateRejectsOutOfRange) {
  EXPECT_NO_THROW(DpoConfig{}.validate());
  const auto expectReject = [](auto mutate, const std::string& field) {
    expectRejected<DpoBatch, DpoConfig>(mutate, field);
  };
  expectReject([](DpoConfig& c) { c.pheromone_decay = 1.0; }, "pheromone_decay");
  expectReject([](DpoConfig& c) { c.pheromone_decay = -1e-6; }, "pheromone_decay");
  expectReject([](DpoConfig& c) { c.pheromone_initial = std::nan(""); }, "pheromone_initial");
  expectReject([](DpoConfig& c) { c.new_place_distance = -0.1; }, "new_place_distance");
  expectReject([](DpoConfig& c) { c.exclusion_radius = -0.1; }, "exclusion_radius");
  expectReject([](DpoConfig& c) { c.arrival_tolerance = 0.0; }, "arrival_tolerance");
  expectReject([](DpoConfig& c) { c.slowing_radius = 11.0; }, "slowing_radius");
  expectReject([](DpoConfig& c) { c.vector_force = 0.0; }, "vector_force");
  expectReject([](DpoConfig& c) { c.collision_window = 2000000; }, "collision_window");
  expectReject([](DpoConfig& c) { c.recovery_spin_ticks = 1001; }, "recovery_spin_ticks");
  expectReject([](DpoConfig& c) { c.recovery_max_offset = 4.0; }, "recovery_max_offset");
  expectReject([](DpoConfig& c) { c.recovery_heading_tolerance = 0.0; }, "recovery_heading_tolerance");
  expectReject([](DpoConfig& c) { c.slowing_speed_min = 20.0; }, "slowing_speed_min");
  expectReject([](DpoConfig& c) { c.recovery_spin_speed = 1.5; }, "recovery_spin_speed");
  expectReject([](DpoConfig& c) { c.recovery_straight_ticks = 5000; }, "recovery_straight_ticks");
  expectReject([](DpoConfig& c) { c.recovery_straight_speed = 0.0; }, "recovery_straight_speed");
  expectReject([](DpoConfig& c) { c.los_cell = 0.0; }, "los_cell");
  expectReject([](DpoConfig& c) { c.los_radius = -1; }, "los_radius");
  expectReject([](DpoConfig& c) { c.nest_center.x() = INFINITY; }, "nest_center");
  expectReject([](DpoConfig& c) { c.explore.wander_force = 0.0; }, "wander_force");
  try {
    DpoConfig c;
    c.pheromone_decay = 2.0;
    c.validate();
  } catch (const ParameterError& e) {
    EXPECT_STREQ(e.what(), "dpo/pheromone_decay must be in [0, 1)");
  }
}

TEST(ControllerFactory, MakesEveryKindAndRejectsUnknownOnes) {
  const ControllerConfigs configs;
  for (const std::string& kind : controllerNames()) {
    const auto c = makeController(kind, configs, 1, 4, 3);
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->name(), kind);
    SensorData s;
    s.resize(8);
    CommandData cmd;
    ControllerStatus status;
    c->step(0, s, cmd, status);
    EXPECT_EQ(cmd.first_id, 4u);
    EXPECT_EQ(cmd.size(), 3u);
  }
  try {
    makeController("levy", configs, 1, 0, 1);
    FAIL() << "no exception";
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("controller 'levy' is unknown; valid: crw, dpo, gp_dpo", 0), 0u);
  }
  ControllerConfigs bad;
  bad.of<DpoConfig>("dpo").arrival_tolerance = -1;
  EXPECT_THROW(makeController("dpo", bad, 1, 0, 1), ParameterError);
}

}  // namespace
}  // namespace swarm_forage
