// FORDYCA 2019's controller-side quirks (1)-(5) against hand-built cases (docs/FIDELITY.md, "FORDYCA as it
// ran"), the parsing of ~model and ~quirks, and fordyca_2019 runs bit-identical for any thread count and
// split of the robots between batches.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "sharing_pool.hpp"
#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/controllers/crw.hpp"
#include "swarm_forage/core/controllers/dpo.hpp"
#include "swarm_forage/core/run/simulation.hpp"
#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {
namespace {

FordycaQuirks only(std::initializer_list<Quirk> qs) {
  FordycaQuirks q;
  for (Quirk k : qs) q.set(k);
  return q;
}

/// A DPO batch with its per-robot quirk state in view.
class DpoProbe : public DpoBatch {
 public:
  DpoProbe(FordycaQuirks q, uint32_t count = 1) : DpoBatch(withQuirks(q), 9, 0, count) {}
  static DpoConfig withQuirks(FordycaQuirks q) {
    DpoConfig c;
    c.explore.quirks = q;
    return c;
  }
  using DpoBatch::heading;
  float recoveryHeading(uint32_t l) const { return recovery_heading_[l]; }
  double driveSpeed(uint32_t l) const { return drive_speed_[l]; }
};

class CrwProbe : public CrwBatch {
 public:
  explicit CrwProbe(FordycaQuirks q) : CrwBatch(withQuirks(q), 4, 0, 1) {}
  static CrwConfig withQuirks(FordycaQuirks q) {
    CrwConfig c;
    c.quirks = q;
    return c;
  }
  float wanderAngle() const { return wander_angle_[0]; }
};

/// One robot at (x, y) with a block `dx, dy` away in its line of sight (DPO vectors to it).
struct OneRobot {
  SensorData s;
  CommandData cmd;
  ControllerStatus status;
  OneRobot(float x, float y, float theta) {
    s.resize(1);
    s.x[0] = x;
    s.y[0] = y;
    s.theta[0] = theta;
  }
  void block(int32_t id, float bx, float by) {
    s.clearLineOfSight();
    s.los_block_offset = {0, 1};
    s.los_block_id = {id};
    s.los_block_x = {bx};
    s.los_block_y = {by};
  }
};

// (5) sensing_subsystem::heading(): position - previous position; the first previous position is (0, 0).
TEST(QuirkHeadingEstimate, FromTheLastTwoPositions) {
  DpoProbe dpo(only({Quirk::kHeadingEstimate}));
  OneRobot r(3.f, 4.f, 2.5f);
  dpo.step(0, r.s, r.cmd, r.status);
  EXPECT_DOUBLE_EQ(dpo.heading(0, 0, r.s), std::atan2(4.0, 3.0));  // tick 0: the angle of the position
  dpo.step(1, r.s, r.cmd, r.status);
  EXPECT_EQ(dpo.heading(0, 0, r.s), 0.0);  // at rest: atan2(0, 0) = 0, whatever the pose says (2.5 rad)
  dpo.step(2, r.s, r.cmd, r.status);
  EXPECT_EQ(dpo.heading(0, 0, r.s), 0.0);
  r.s.x[0] = 2.9f;  // moved west by 0.1 m
  dpo.step(3, r.s, r.cmd, r.status);
  EXPECT_DOUBLE_EQ(dpo.heading(0, 0, r.s), std::atan2(0.0, static_cast<double>(2.9f) - 3.0));
  DpoProbe exact(FordycaQuirks{});
  exact.step(0, r.s, r.cmd, r.status);
  EXPECT_EQ(exact.heading(0, 0, r.s), 2.5f);  // the default model: the pose
}

// (5) steers by the estimate: a robot at rest facing north (pose) vectors as if it faced east.
TEST(QuirkHeadingEstimate, AtRestItSteersAsIfFacingEast) {
  for (const bool quirk : {false, true}) {
    DpoProbe dpo(quirk ? only({Quirk::kHeadingEstimate}) : FordycaQuirks{});
    OneRobot r(1.1f, 1.1f, static_cast<float>(kPi / 2));
    r.block(7, 1.4f, 1.1f);  // 0.3 m east
    dpo.step(0, r.s, r.cmd, r.status);
    dpo.step(1, r.s, r.cmd, r.status);  // at rest: estimate 0
    ASSERT_EQ(dpo.state(0), DpoState::kVector);
    if (quirk) {
      EXPECT_EQ(r.cmd.left[0], r.cmd.right[0]);  // straight ahead
    } else {
      EXPECT_GT(r.cmd.left[0], r.cmd.right[0]);  // a right turn toward the east
    }
  }
}

/// Robot 0 vectoring to a block 0.3 m east (outside the slowing radius); threatened at `threat_tick`.
void collideAt(DpoProbe& dpo, OneRobot& r, uint64_t threat_tick) {
  r.block(7, r.s.x[0] + 0.3f, r.s.y[0]);
  for (uint64_t t = 0; t <= threat_tick; ++t) {
    r.s.threatened[0] = t == threat_tick;
    r.s.obstacle_x[0] = 0.1f;
    dpo.step(t, r.s, r.cmd, r.status);
  }
}

// (3) last_collision_time starts at 0: a first collision at tick 100 is a second one.
TEST(QuirkFirstCollisionAtZero, ACollisionAtTick100CountsAsASecondOne) {
  for (const bool quirk : {false, true}) {
    DpoProbe dpo(quirk ? only({Quirk::kFirstCollisionAtZero}) : FordycaQuirks{});
    OneRobot r(1.1f, 1.1f, 0.f);
    collideAt(dpo, r, 100);
    ASSERT_EQ(dpo.state(0), DpoState::kVector);
    EXPECT_EQ(dpo.recovering(0), quirk) << quirk;  // a new direction, spinning
    EXPECT_EQ(dpo.avoiding(0), !quirk) << quirk;   // plain avoidance
  }
  // This model's tick t is ARGoS' clock t + 1: the last tick that counts is 298 (clock 299).
  for (const uint64_t tick : {298u, 299u}) {
    DpoProbe late(only({Quirk::kFirstCollisionAtZero}));
    OneRobot r(1.1f, 1.1f, 0.f);
    collideAt(late, r, tick);
    EXPECT_EQ(late.recovering(0), tick == 298u) << tick;
  }
}

// (2) randomize_vector_angle(X): the new direction is U[0, 1] rad in the world, whatever the heading;
// the default model draws it U[0, 1] rad off the heading.
TEST(QuirkAbsoluteRecoveryAngle, TheNewDirectionLiesInTheAbsoluteWindow) {
  int outside_window_by_default = 0;
  for (int k = 0; k < 60; ++k) {
    const float theta = static_cast<float>(-3.0 + 0.1 * k);
    for (const bool quirk : {false, true}) {
      FordycaQuirks q = only({Quirk::kFirstCollisionAtZero});
      if (quirk) q.set(Quirk::kAbsoluteRecoveryAngle);
      DpoProbe dpo(q);
      OneRobot r(1.1f, 1.1f, theta);
      collideAt(dpo, r, 5 + static_cast<uint64_t>(k));
      ASSERT_TRUE(dpo.recovering(0));
      const double h = dpo.recoveryHeading(0);
      if (quirk) {
        EXPECT_GE(h, 0.0) << theta;
        EXPECT_LE(h, 1.0) << theta;
      } else {
        const double off = wrapAngle(h - theta);
        EXPECT_GE(off, -1e-6) << theta;
        EXPECT_LE(off, 1.0 + 1e-6) << theta;
        outside_window_by_default += h < 0.0 || h > 1.0;
      }
    }
  }
  EXPECT_GT(outside_window_by_default, 30);
}

// (2) FORDYCA's new_direction turns by current_dir - new_dir (> 0: left): away from the new direction.
TEST(QuirkAbsoluteRecoveryAngle, SpinsAsFordycaDoes) {
  DpoProbe dpo(only({Quirk::kFirstCollisionAtZero, Quirk::kAbsoluteRecoveryAngle}));
  OneRobot r(1.1f, 1.1f, -2.0f);  // heading -2 rad, new direction in [0, 1]: current - new < 0
  collideAt(dpo, r, 3);
  ASSERT_TRUE(dpo.recovering(0));
  EXPECT_GT(r.cmd.left[0], 0.f);  // a right (clockwise) turn in place
  EXPECT_LT(r.cmd.right[0], 0.f);
  EXPECT_EQ(r.cmd.left[0], -r.cmd.right[0]);
}

// (4) rcppsw arrival_force: vector2d(m, angle_diff) (Cartesian), so the command is atan2(delta, m).
TEST(QuirkCompressedArrival, TheHeadingCommandIsAtan2OfDeltaAndM) {
  const DriveConfig drive;
  const double m = DpoConfig{}.vector_force, phi = 2.0;  // the block 2 rad to the left, 0.3 m away
  DpoProbe dpo(only({Quirk::kCompressedArrival}));
  OneRobot r(1.1f, 1.1f, 0.f);
  const float bx = static_cast<float>(1.1 + 0.3 * std::cos(phi)),
              by = static_cast<float>(1.1 + 0.3 * std::sin(phi));
  r.block(7, bx, by);
  dpo.step(0, r.s, r.cmd, r.status);
  ASSERT_EQ(dpo.state(0), DpoState::kVector);
  // Tick 0: current_speed 0, linear_velocity() = (+0, +0), its angle 0.
  const double a = std::atan2(static_cast<double>(by) - static_cast<double>(1.1f),
                              static_cast<double>(bx) - static_cast<double>(1.1f)) -
                   0.0;
  const double delta = std::atan2(std::sin(a), std::cos(a));
  WheelSpeeds want = steer(Vec2(m, delta), drive, true);
  EXPECT_EQ(r.cmd.left[0], want.left);
  EXPECT_EQ(r.cmd.right[0], want.right);
  // ... which is a heading error of atan2(delta, m) = 14 deg (not 115): a soft left turn, both wheels
  // forward.
  EXPECT_NEAR(std::atan2(delta, m), 0.245, 0.001);
  EXPECT_GT(r.cmd.right[0], r.cmd.left[0]);
  EXPECT_GT(r.cmd.left[0], 0.f);
  EXPECT_GT(dpo.driveSpeed(0), 0.1);
  // The default model turns by the true 115 degrees: forced soft turn, the inner wheel reversed.
  DpoProbe exact(FordycaQuirks{});
  OneRobot e(1.1f, 1.1f, 0.f);
  e.block(7, bx, by);
  exact.step(0, e.s, e.cmd, e.status);
  EXPECT_LT(e.cmd.left[0], 0.f);
  // Tick 1: moving forward, so the velocity's angle is the heading (0); then the block moves to the other
  // side: delta = -3.0 is unwrapped against the last one (|-3 - 2| > pi): -3 + 2 pi.
  const float cx = static_cast<float>(1.1 + 0.3 * std::cos(-3.0)),
              cy = static_cast<float>(1.1 + 0.3 * std::sin(-3.0));
  r.block(7, cx, cy);
  dpo.step(1, r.s, r.cmd, r.status);
  const double a2 = std::atan2(static_cast<double>(cy) - static_cast<double>(1.1f),
                               static_cast<double>(cx) - static_cast<double>(1.1f)) -
                    0.0;
  const double d2 = std::atan2(std::sin(a2), std::cos(a2));
  want = steer(Vec2(m, d2 + 2 * kPi), drive, true);
  EXPECT_EQ(r.cmd.left[0], want.left);
  EXPECT_EQ(r.cmd.right[0], want.right);
}

/// Takes a CRW robot to transport (explore 50 ticks, a block, carrying); returns the next tick.
uint64_t toTransport(CrwBatch& crw, OneRobot& r) {
  uint64_t t = 0;
  for (; t < 50; ++t) crw.step(t, r.s, r.cmd, r.status);
  r.s.ground[0] = kBlockGround;
  crw.step(t++, r.s, r.cmd, r.status);
  r.s.ground[0] = kFloor;
  r.s.carried_block[0] = 3;
  r.s.events[0] = kPickupDone;
  crw.step(t++, r.s, r.cmd, r.status);
  r.s.events[0] = 0;
  return t;
}

// (1) transport_to_nest: wander added when not threatened and |linear_velocity()| <= 0.1 cm/s.
TEST(QuirkTransportWander, OnlyWhenNearlyStoppedAndNotThreatened) {
  const CrwConfig c;
  struct Case {
    float light_before;  // light x of the tick before: -1 (behind: wheels clamped at -+max, mean 0) or 1
    bool threat;
    bool wander;  // expected
  };
  for (const Case k : {Case{-1.f, false, true}, Case{1.f, false, false}, Case{-1.f, true, false}}) {
    CrwProbe crw(only({Quirk::kTransportWander})), plain(FordycaQuirks{});
    OneRobot r(5.f, 5.f, 0.f), p(5.f, 5.f, 0.f);
    uint64_t t = toTransport(crw, r);
    toTransport(plain, p);
    ASSERT_EQ(crw.state(0), CrwState::kTransport);
    for (OneRobot* o : {&r, &p}) {
      o->s.light_x[0] = k.light_before;
      o->s.light_y[0] = 0.f;
    }
    crw.step(t, r.s, r.cmd, r.status);
    plain.step(t, p.s, p.cmd, p.status);
    ++t;
    for (OneRobot* o : {&r, &p}) {
      o->s.light_x[0] = 1.f;
      o->s.threatened[0] = k.threat;
      o->s.obstacle_x[0] = 0.05f;
      o->s.obstacle_y[0] = 0.05f;
    }
    float angle = crw.wanderAngle();
    CounterRng rng(4, RngStream::kController, 0, t);
    const Vec2 photo(c.phototaxis_force, 0);
    const WheelSpeeds with_wander = steer(photo + wanderForce(angle, rng, c), c.drive, true);
    crw.step(t, r.s, r.cmd, r.status);
    plain.step(t, p.s, p.cmd, p.status);
    if (k.wander) {
      EXPECT_EQ(r.cmd.left[0], with_wander.left);
      EXPECT_EQ(r.cmd.right[0], with_wander.right);
      EXPECT_NE(r.cmd.left[0], p.cmd.left[0]);
    } else {
      EXPECT_EQ(r.cmd.left[0], p.cmd.left[0]) << k.light_before << " " << k.threat;
      EXPECT_EQ(r.cmd.right[0], p.cmd.right[0]);
    }
  }
}

// (1) vector_fsm's collision avoidance adds the wander force on the same test.
TEST(QuirkTransportWander, VectoringAvoidanceAddsWanderWhenNearlyStopped) {
  const CrwConfig c;
  for (const bool quirk : {false, true}) {
    DpoProbe dpo(quirk ? only({Quirk::kTransportWander}) : FordycaQuirks{});
    OneRobot r(1.1f, 1.1f, 0.f);
    collideAt(dpo, r, 0);  // tick 0: the speed estimate is 0 (nothing driven yet); a first collision
    ASSERT_TRUE(dpo.avoiding(0));
    const Vec2 avoid = avoidanceForce(r.s, 0, c.avoidance_force);  // the obstacle straight ahead
    float angle = 0.f;
    CounterRng rng(9, RngStream::kController, 0, 0);
    const WheelSpeeds want =
        quirk ? steer(avoid + wanderForce(angle, rng, c), c.drive, false) : steer(avoid, c.drive, false);
    EXPECT_EQ(r.cmd.left[0], want.left) << quirk;
    EXPECT_EQ(r.cmd.right[0], want.right) << quirk;
  }
}

// ~model and ~quirks.
TEST(FordycaQuirksParse, ModelsQuirksAndRefusals) {
  EXPECT_FALSE(FordycaQuirks::parse("swarm_forage", "").any());
  const FordycaQuirks f = FordycaQuirks::parse("fordyca_2019", "");
  for (const QuirkInfo& i : quirkList())
    EXPECT_EQ(f.has(i.quirk), i.quirk != Quirk::kDynamics2dContacts) << i.name;
  EXPECT_EQ(f.controllerSide(),
            only({Quirk::kTransportWander, Quirk::kAbsoluteRecoveryAngle, Quirk::kFirstCollisionAtZero,
                  Quirk::kCompressedArrival, Quirk::kHeadingEstimate}));
  EXPECT_EQ(FordycaQuirks::parse("swarm_forage", " heading_estimate , compressed_arrival"),
            only({Quirk::kHeadingEstimate, Quirk::kCompressedArrival}));
  const auto message = [](const std::string& model, const std::string& quirks) {
    try {
      FordycaQuirks::parse(model, quirks);
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string bad_model = message("fordyca", "");
  EXPECT_NE(bad_model.find("swarm_forage"), std::string::npos) << bad_model;
  EXPECT_NE(bad_model.find("fordyca_2019"), std::string::npos) << bad_model;
  const std::string bad_quirk = message("swarm_forage", "transport_wander,heading");
  for (const QuirkInfo& i : quirkList()) EXPECT_NE(bad_quirk.find(i.name), std::string::npos) << bad_quirk;
  EXPECT_NE(bad_quirk.find("'heading'"), std::string::npos) << bad_quirk;
}

TEST(FordycaQuirksParse, IdentityWordsOnlyWhenOn) {
  ControllerConfigs c;
  EXPECT_EQ(describeConstants("dpo", c).find("quirks"), std::string::npos);
  c.quirks = FordycaQuirks::parse("fordyca_2019", "");
  const std::string d = describeConstants("dpo", c);
  EXPECT_NE(
      d.find("quirks=transport_wander,absolute_recovery_angle,first_collision_at_zero,compressed_arrival,"
             "heading_estimate"),
      std::string::npos)
      << d;
  EXPECT_EQ(d.find("rim_ground_sensors"), std::string::npos) << d;  // the world's, not the controllers'
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// fordyca_2019: bit-identical for 1 and 2 threads, and for the robots split into two batches.
TEST(FordycaQuirksDeterminism, ThreadsAndSplits) {
  for (const std::string kind : {"crw", "dpo", "gp_dpo"}) {
    WorldConfig w;
    w.n_robots = 1024;
    w.seed = 3;
    w.quirks = FordycaQuirks::parse("fordyca_2019", "");
    ControllerConfigs cc;
    cc.quirks = w.quirks;
    Simulation one(w, kind, cc, 1), two(w, kind, cc, sharingPool(2));
    WorldConfig w_plain = w;
    w_plain.quirks = FordycaQuirks{};
    Simulation plain(w_plain, kind, ControllerConfigs{}, 1);  // the quirks must change something
    bool differs = false;
    const WorldConfig& wc = one.world().config();
    const Rect n = wc.arena.nest();
    const ControllerConfigs shared = sharingWorld(
        cc, {static_cast<float>((n.min_x + n.max_x) / 2), static_cast<float>((n.min_y + n.max_y) / 2)},
        {static_cast<float>(wc.sight.cell), wc.sight.radius});
    const uint32_t half = 389;  // uneven on purpose
    auto lo = makeController(kind, shared, wc.seed, 0, half),
         hi = makeController(kind, shared, wc.seed, half, w.n_robots - half);
    CommandData cl, ch;
    ControllerStatus sl, sh;
    for (uint64_t t = 0; t < 400; ++t) {
      one.step();
      two.step();
      ASSERT_TRUE(sameBits(one.world().robots().x, two.world().robots().x)) << kind << " tick " << t;
      ASSERT_TRUE(sameBits(one.commands().left, two.commands().left)) << kind << " tick " << t;
      ASSERT_TRUE(sameBits(one.commands().right, two.commands().right)) << kind << " tick " << t;
      plain.step();
      differs = differs || !sameBits(one.commands().left, plain.commands().left);
      lo->step(t, one.sensors(), cl, sl);
      hi->step(t, one.sensors(), ch, sh);
      for (uint32_t i = 0; i < w.n_robots; ++i) {
        const CommandData& part = i < half ? cl : ch;
        const uint32_t l = i < half ? i : i - half;
        ASSERT_EQ(std::memcmp(&part.left[l], &one.commands().left[i], sizeof(float)), 0)
            << kind << " " << t << " " << i;
        ASSERT_EQ(std::memcmp(&part.right[l], &one.commands().right[i], sizeof(float)), 0)
            << kind << " " << t;
        ASSERT_EQ(part.request[l], one.commands().request[i]) << kind << " " << t;
      }
    }
    EXPECT_GT(one.status().in_avoidance, 0u) << kind;
    EXPECT_TRUE(differs) << kind;
  }
}

}  // namespace
}  // namespace swarm_forage
