// FORDYCA 2019's world-side quirks on hand-built cases (docs/FIDELITY.md, "FORDYCA as it ran", (6)-(8)):
// the rim ground sensors, the block operation penalties and the light occlusion; and runs with them on are
// bit-identical for 1 and 2 threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "swarm_forage/core/run/simulation.hpp"
#include "swarm_forage/core/util/simd.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {
namespace {

WorldConfig withQuirks(std::initializer_list<Quirk> quirks, uint32_t n = 1) {
  WorldConfig c;  // 32 x 16 m: the nest is x in [1.6, 4.8], y in [1.6, 14.4]; lights at x 3.2, y 4.8, 8, 11.2
  c.n_robots = n;
  c.seed = 1;
  for (Quirk q : quirks) c.quirks.set(q);
  return c;
}

/// Robots parked far apart in the open (away from the nest, the source and the walls).
void park(World& w) {
  for (uint32_t i = 0; i < w.robots().size(); ++i)
    w.setPose(i, 8.0 + 1.0 * (i % 10), 2.0 + 1.0 * (i / 10), 0.0);
}

uint8_t groundOf(World& w, uint32_t i = 0) {
  SensorData s;
  w.sense(s);
  return s.ground[i];
}

CommandData stopAll(std::size_t n) {
  CommandData c;
  c.resize(n);
  return c;
}

/// A block with no other block within 0.6 m of its centre.
int32_t lonelyBlock(const World& w) {
  const BlockField& b = w.blocks();
  for (int32_t i = 0; i < static_cast<int32_t>(b.size()); ++i) {
    if (b.kind(i) != kCube) continue;
    bool alone = true;
    for (int32_t j = 0; j < static_cast<int32_t>(b.size()); ++j)
      if (j != i && std::hypot(b.x(j) - b.x(i), b.y(j) - b.y(i)) < 0.6) alone = false;
    if (alone) return i;
  }
  return -1;
}

// (6) ARGoS' motor ground sensors at (+-0.063, +-0.0116) m; FORDYCA's in_nest: 3 of 4 read the nest's grey.
TEST(QuirksWorld, RimSensorsThreeOfFourGreyIsTheNest) {
  World rim(withQuirks({Quirk::kRimGroundSensors}));
  World centre(withQuirks({}));
  const double edge = 4.8, th = kPi / 4;  // heading 45 deg: the sensors sit at x offsets +-0.0363, +-0.0528
  // Centre 4.5 cm inside the nest's east edge: 3 sensors inside (x - 0.0528, x - 0.0363, x + 0.0363), 1 out.
  rim.setPose(0, edge - 0.045, 8.0, th);
  EXPECT_EQ(groundOf(rim), kNest);
  // Centre 1 cm inside: 2 sensors inside, 2 out: not the nest, though the centre is in it.
  rim.setPose(0, edge - 0.01, 8.0, th);
  EXPECT_EQ(groundOf(rim), kFloor);
  centre.setPose(0, edge - 0.01, 8.0, th);
  EXPECT_EQ(groundOf(centre), kNest);  // the default model reads the centre
  // Deep inside: all four.
  rim.setPose(0, 3.0, 8.0, 0.3);
  EXPECT_EQ(groundOf(rim), kNest);
}

TEST(QuirksWorld, RimSensorsSeeABlockOnlyWhenAllFourReadBlack) {
  World rim(withQuirks({Quirk::kRimGroundSensors}));
  World centre(withQuirks({}));
  const int32_t b = lonelyBlock(rim);
  ASSERT_GE(b, 0);
  const double bx = rim.blocks().x(b), by = rim.blocks().y(b);  // a 0.2 m cube
  rim.setPose(0, bx, by, 0.0);
  EXPECT_EQ(groundOf(rim), kBlockGround);
  // 5 cm ahead of the cube's centre, heading along x: the front sensors (x + 0.063) are off the cube.
  rim.setPose(0, bx + 0.05, by, 0.0);
  EXPECT_EQ(groundOf(rim), kFloor);
  centre.setPose(0, bx + 0.05, by, 0.0);
  EXPECT_EQ(groundOf(centre), kBlockGround);
  // Turned by 90 deg the sensors span only +-0.0116 m along x: all four on the cube again.
  rim.setPose(0, bx + 0.05, by, kPi / 2);
  EXPECT_EQ(groundOf(rim), kBlockGround);
}

// (6) and the world: FORDYCA's nest drop counts when the robot's sensors say in_nest.
TEST(QuirksWorld, RimSensorsDecideANestDrop) {
  for (const bool quirk : {false, true}) {
    World w(quirk ? withQuirks({Quirk::kRimGroundSensors}) : withQuirks({}));
    const int32_t b = lonelyBlock(w);
    w.setPose(0, w.blocks().x(b), w.blocks().y(b), 0.0);
    CommandData cmd = stopAll(1);
    cmd.request[0] = kPickup;
    w.step(cmd, 0.0);
    ASSERT_EQ(w.robots().carried[0], b);
    w.setPose(0, 4.8 - 0.01, 8.0, kPi / 4);  // centre in the nest, 2 of 4 sensors on its grey
    cmd.request[0] = kDrop;
    EXPECT_EQ(w.step(cmd, 0.0).delivered, quirk ? 0u : 1u) << quirk;
  }
}

// (7) FORDYCA's penalty: a pick-up requested at tick t finishes at tick t + 1 (the Null waveform's 0 counts
// as 1), one robot per tick swarm wide (deconflict_penalty_finish), robots in ARGoS' id order ("10" < "2").
TEST(QuirksWorld, PenaltiesFinishPickupsOnePerTickInArgosOrder) {
  World w(withQuirks({Quirk::kBlockPenalties}, 11));
  park(w);
  const std::vector<uint32_t> robots{2, 10, 3};
  for (std::size_t k = 0; k < robots.size(); ++k)
    w.setPose(robots[k], w.blocks().x(static_cast<int32_t>(k)), w.blocks().y(static_cast<int32_t>(k)), 0.0);
  CommandData cmd = stopAll(11);
  for (uint32_t r : robots) cmd.request[r] = kPickup;
  w.step(cmd, 0.0);  // tick 0: the penalties start, none finishes
  EXPECT_EQ(w.carrying(), 0u);
  EXPECT_EQ(w.pickupPenalties().size(), 3u);
  w.step(cmd, 0.0);  // tick 1: robot 10 first ("fb10" < "fb2" < "fb3")
  EXPECT_EQ(w.robots().carried[10], 1);
  EXPECT_EQ(w.carrying(), 1u);
  EXPECT_EQ(w.robots().events[2], 0) << "a waiting robot hears nothing";
  w.step(cmd, 0.0);
  EXPECT_EQ(w.robots().carried[2], 0);
  EXPECT_EQ(w.carrying(), 2u);
  w.step(cmd, 0.0);
  EXPECT_EQ(w.robots().carried[3], 2);
  EXPECT_EQ(w.pickupPenalties().size(), 0u);

  // Nest drops: the same, one per tick after the penalty.
  for (std::size_t k = 0; k < robots.size(); ++k) w.setPose(robots[k], 3.2, 6.0 + 1.0 * k, 0.0);
  for (uint32_t r : robots) cmd.request[r] = kDrop;
  EXPECT_EQ(w.step(cmd, 0.0).delivered, 0u);
  EXPECT_EQ(w.step(cmd, 0.0).delivered, 1u);
  EXPECT_EQ(w.step(cmd, 0.0).delivered, 1u);
  EXPECT_EQ(w.step(cmd, 0.0).delivered, 1u);
  EXPECT_EQ(w.carrying(), 0u);

  // Without the quirk all three pick-ups finish at once.
  World free(withQuirks({}, 11));
  park(free);
  for (std::size_t k = 0; k < robots.size(); ++k)
    free.setPose(robots[k], free.blocks().x(static_cast<int32_t>(k)),
                 free.blocks().y(static_cast<int32_t>(k)), 0.0);
  CommandData all = stopAll(11);
  for (uint32_t r : robots) all.request[r] = kPickup;
  free.step(all, 0.0);
  EXPECT_EQ(free.carrying(), 3u);
}

// serialize_block_ops stays the world's own queue; with block_penalties the quirk's handlers replace it.
TEST(QuirksWorld, PenaltiesReplaceSerializeBlockOps) {
  std::vector<uint32_t> done[2];
  for (const bool serialize : {false, true}) {
    WorldConfig c = withQuirks({Quirk::kBlockPenalties}, 11);
    c.serialize_block_ops = serialize;
    World w(c);
    park(w);
    for (uint32_t r : {2u, 10u, 3u}) w.setPose(r, w.blocks().x(r % 3), w.blocks().y(r % 3), 0.0);
    CommandData cmd = stopAll(11);
    for (uint32_t r : {2u, 10u, 3u}) cmd.request[r] = kPickup;
    for (int t = 0; t < 4; ++t) {
      w.step(cmd, 0.0);
      done[serialize].push_back(w.carrying());
    }
  }
  EXPECT_EQ(done[0], done[1]);
  EXPECT_EQ(done[0], (std::vector<uint32_t>{0, 1, 2, 3}));
}

// FORDYCA's deconfliction loop restarts at the list's second entry after a clash: a third penalty can end
// at the same tick as the first.
TEST(QuirksWorld, DeconflictionKeepsFordycasLoop) {
  BlockPenaltyHandler h;
  h.reset(3);
  h.start(0, 5, 0, 2);  // finishes at 2
  h.start(1, 6, 0, 0);  // 0 counts as 1: finishes at 1
  EXPECT_EQ(h.of(1).penalty, 1u);
  EXPECT_EQ(h.deconflict(0, 0), 2u);  // clashes with 1's tick 1, then 0's tick 2 is not looked at again
  h.start(2, 7, 1, 0);                // at tick 1: finishing at 2 clashes with robot 0, so at 3 (penalty 2)
  EXPECT_EQ(h.of(2).penalty, 2u);
  EXPECT_TRUE(h.satisfied(1, 1));
  EXPECT_FALSE(h.satisfied(0, 1));
  h.remove(1);
  EXPECT_FALSE(h.serving(1));
  EXPECT_EQ(h.size(), 2u);
}

// The controller waits on the block during the penalty: a CRW robot asking for a pick-up stands still
// until the pick-up is done.
TEST(QuirksWorld, RobotsWaitStoppedDuringThePenalty) {
  WorldConfig c = withQuirks({Quirk::kBlockPenalties}, 64);
  c.seed = 3;
  Simulation sim(c, "crw", ControllerConfigs{}, 1);
  uint32_t waited = 0, pickups = 0;
  for (int t = 0; t < 3000; ++t) {
    const std::vector<double> x0 = sim.world().robots().x, y0 = sim.world().robots().y;
    const std::vector<int32_t> held = sim.world().robots().carried;
    sim.step();
    const CommandData& cmd = sim.commands();
    for (uint32_t i = 0; i < 64; ++i) {
      if (cmd.request[i] != kPickup) continue;
      ++waited;
      EXPECT_EQ(cmd.left[i], 0.f);
      EXPECT_EQ(cmd.right[i], 0.f);
      EXPECT_EQ(sim.world().robots().x[i], x0[i]) << "tick " << t;  // nobody pushes a lone waiting robot
      if (held[i] < 0 && sim.world().robots().carried[i] >= 0) ++pickups;
    }
  }
  EXPECT_GT(pickups, 0u);
  EXPECT_GE(waited, 2 * pickups) << "each pick-up waits at least the tick it asks and the penalty's";
}

// (8) ARGoS' light sensor: the ray from the robot's origin (z = 0) to a light is occluded by a body it
// enters below the body's height (0.147 m). The centre light stands at z = 1, the outer two at z = 5.
TEST(QuirksWorld, ARobotOnTheLineShadowsALight) {
  World w(withQuirks({Quirk::kLightOcclusion}, 2));
  SensorData s;
  const double d0 = std::hypot(16.8, 3.2), all = -(1 + 2 * 16.8 / d0), outer = -2 * 16.8 / d0;
  // Robot 0 in line with the centre light (3.2, 8, 1), 16.8 m away; its light vector (robot frame, heading
  // 0) is the sum of the unit vectors to the lights it sees: `all`, or `outer` without the centre one.
  const auto light0 = [&](double x1, double y1, double th1) {
    w.setPose(0, 20.0, 8.0, 0.0);
    w.setPose(1, x1, y1, th1);
    w.sense(s);
    EXPECT_NEAR(s.light_y[0], 0.0, 1e-5);
    return s.light_x[0];
  };
  // 1 m toward the light: entered at 0.915 m, where the ray is 0.054 m high.
  EXPECT_NEAR(light0(19.0, 8.0, 0.0), outer, 1e-5);
  EXPECT_EQ(w.shadowedLights(), 1u);
  EXPECT_NEAR(light0(19.0, 9.0, 0.0), all, 1e-5);  // 1 m off the line
  EXPECT_NEAR(light0(15.0, 8.0, 0.0), all, 1e-5);  // 5 m toward the light: the ray passes 0.29 m above it
  EXPECT_NEAR(light0(21.0, 8.0, 0.0), all, 1e-5);  // behind robot 0 (which shadows robot 1's instead)
  EXPECT_EQ(w.shadowedLights(), 1u);
  EXPECT_NEAR(light0(19.0, 8.09, 0.0), all, 1e-5);  // 9 cm off the line: the body (8.5 cm) misses it ...
  EXPECT_NEAR(light0(19.0, 8.09, -kPi / 2), outer, 1e-5);  // ... its gripper, on the rim facing the line, not
  EXPECT_NEAR(light0(19.0, 8.09, kPi / 2), all, 1e-5);

  // An outer light at z = 5, (3.2, 4.8): a body shadows it only within 0.79 m of a robot 26.8 m away
  // (5 cm off the line, so that the centre light's ray passes by).
  w.setPose(0, 30.0, 4.8, 0.0);
  w.setPose(1, 29.4, 4.75, 0.0);
  w.sense(s);
  EXPECT_EQ(w.shadowedLights(), 1u);
  w.setPose(1, 29.0, 4.75, 0.0);  // entered 0.93 m away: the ray is 0.17 m high there
  w.sense(s);
  EXPECT_EQ(w.shadowedLights(), 0u);

  // Without the quirk no light is ever shadowed.
  World plain(withQuirks({}, 2));
  plain.setPose(0, 20.0, 8.0, 0.0);
  plain.setPose(1, 19.0, 8.0, 0.0);
  plain.sense(s);
  EXPECT_NEAR(s.light_x[0], all, 1e-5);
}

/// A run of `kind` stepped by hand, with the world's configuration as given: Simulation would set
/// light_only_carrying from the kind, and these tests compare both settings.
struct ByHand {
  ByHand(const WorldConfig& c, const std::string& kind, unsigned threads)
      : pool(std::make_shared<WorkerPool>(threads)), world(c), controllers(ControllerConfigs{}, pool) {
    world.setPool(pool);
    RunDescription run;
    run.controller = kind;
    run.world = world.config();
    controllers.begin(run, world);
  }
  void step() {
    world.sense(sensors);
    controllers.decide(world.tick(), world, sensors);
    world.step(controllers.commands(), {}, controllers.batchStatus().tasks);
  }
  std::shared_ptr<WorkerPool> pool;
  World world;
  InProcessControllers controllers;
  SensorData sensors;
};

// Every (robot, light) shadowed exactly when a test of every other body says so. The walk and the cache of
// last tick's shadowing body choose which bodies to test, never the answer: checked as robots move, in a
// crowd and sparse, for 1 and 2 threads.
uint8_t bruteForceMask(const RobotBodies& b, const WorldConfig& c, uint32_t i) {
  uint8_t mask = 0;
  for (int l = 0; l < ArenaConfig::kLights; ++l) {
    const Vec2 p = c.arena.light(l);
    for (uint32_t k = 0; k < b.size(); ++k)
      if (k != i && footBotShadows(b.x[i], b.y[i], p.x(), p.y(), kFordycaLightHeight[l], b.x[k], b.y[k],
                                   b.theta[k], c.robot.radius)) {
        mask |= static_cast<uint8_t>(1u << l);
        break;
      }
  }
  return mask;
}

TEST(QuirksWorld, OcclusionMatchesBruteForceAsRobotsMove) {
  for (const uint32_t n : {1500u, 120u})  // 2.9 and 0.23 robots per square metre in 32 x 16 m
    for (const unsigned threads : {1u, 2u}) {
      WorldConfig c = configuredFor(withQuirks({Quirk::kLightOcclusion}, n), "dpo");
      c.seed = n;
      c.light_only_carrying = false;  // every robot's lights
      ByHand sim(c, "dpo", threads);
      uint64_t total = 0;
      for (int t = 1; t <= 60; ++t) {
        sim.step();
        if (t % 20 != 1) continue;
        SensorData s;
        sim.world.sense(s);  // the poses now; last tick's shadowing bodies are in the cache
        const RobotBodies& b = sim.world.robots();
        uint64_t here = 0;
        for (uint32_t i = 0; i < b.size(); ++i) {
          const uint8_t mask = bruteForceMask(b, c, i);
          ASSERT_EQ(sim.world.shadowMasks()[i], mask)
              << "n " << n << ", " << threads << " threads, tick " << t << ", robot " << i;
          here += static_cast<uint64_t>(__builtin_popcount(mask));
        }
        EXPECT_EQ(sim.world.shadowedLights(), here);
        total += here;
      }
      EXPECT_GT(total, n / 10) << "n " << n << ": shadows must happen for the comparison to mean something";
    }
}

// Long rays nearly along the grid's rows (a 400 m arena whose lights stand in a row at y = 16): a row's
// stretch spans up to 186 cells (the walk's path for more than a load's 56) and holds many bodies (the
// 4-lane test's several steps), with rays exactly along a row and just off it; 4-lane and scalar paths.
TEST(QuirksWorld, OcclusionMatchesBruteForceAlongLongRows) {
  WorldConfig c = withQuirks({Quirk::kLightOcclusion}, 600);
  c.arena.width = 400;
  c.arena.height = 32;
  c.light_only_carrying = false;
  const bool was = simdEnabled();
  for (const bool simd : {true, false}) {
    setSimdEnabled(simd);
    World w(c);
    const double offsets[] = {0.0, 0.03, -0.08, 0.4, -0.25, 1e-10};
    for (uint32_t i = 0; i < 600; ++i) w.setPose(i, 80.0 + 0.5 * i, 16.0 + offsets[i % 6], 0.7 * i);
    SensorData s;
    w.sense(s);
    uint64_t shadowed = 0;
    for (uint32_t i = 0; i < 600; ++i) {
      const uint8_t mask = bruteForceMask(w.robots(), c, i);
      ASSERT_EQ(w.shadowMasks()[i], mask) << "robot " << i << (simd ? ", 4 lanes" : ", scalar");
      shadowed += static_cast<uint64_t>(__builtin_popcount(mask));
    }
    EXPECT_GT(shadowed, 300u);
    EXPECT_LT(shadowed, 3 * 600u - 50u) << "and some not";
  }
  setSimdEnabled(was);
}

// With light_only_carrying (what the built-in kinds declare), carriers' lights are shadowed as the brute
// force says and the others' readings are NaN; and a run's every pose, block and delivery is the same
// bits as with every robot's lights shadowed, for each built-in kind, model fordyca_2019, crowded and
// sparse, 1 and 2 threads: their controllers read the light only while carrying.
TEST(QuirksWorld, ShadowingOnlyCarriersChangesNoRun) {
  struct Case {
    const char* kind;
    uint32_t n, ticks;
    unsigned threads;
  };
  for (const Case k : {Case{"crw", 600, 1500, 1}, Case{"dpo", 600, 1500, 2}, Case{"gp_dpo", 600, 1500, 1},
                       Case{"dpo", 80, 3000, 1}}) {
    WorldConfig c = configuredFor(withQuirks({}, k.n), k.kind);
    c.quirks = FordycaQuirks::parse("fordyca_2019", "");
    c.seed = 7;
    ASSERT_TRUE(c.light_only_carrying) << k.kind << " declares it";
    WorldConfig every = c;
    every.light_only_carrying = false;
    ByHand carriers(c, k.kind, k.threads), all(every, k.kind, k.threads);
    uint64_t carrier_ticks = 0, shadowed = 0;
    for (uint32_t t = 1; t <= k.ticks; ++t) {
      carriers.step();
      all.step();
      const RobotBodies& b = carriers.world.robots();
      for (uint32_t i = 0; i < b.size(); ++i) {
        if (carriers.sensors.carried_block[i] < 0) {
          ASSERT_TRUE(std::isnan(carriers.sensors.light_x[i])) << k.kind << " tick " << t << " robot " << i;
          continue;
        }
        ++carrier_ticks;
        ASSERT_EQ(carriers.world.shadowMasks()[i], all.world.shadowMasks()[i]) << k.kind << " tick " << t;
        shadowed += carriers.world.shadowMasks()[i] != 0;
      }
      if (t % 100 != 0 && t != k.ticks) continue;
      const RobotBodies& a = all.world.robots();
      ASSERT_TRUE(std::memcmp(b.x.data(), a.x.data(), b.size() * sizeof(double)) == 0 &&
                  std::memcmp(b.y.data(), a.y.data(), b.size() * sizeof(double)) == 0 &&
                  std::memcmp(b.theta.data(), a.theta.data(), b.size() * sizeof(double)) == 0 &&
                  b.carried == a.carried)
          << k.kind << " n " << k.n << ": the runs part by tick " << t;
    }
    EXPECT_GT(carrier_ticks, 1000u) << k.kind << ": robots must carry for the comparison to mean something";
    EXPECT_GT(shadowed, 100u) << k.kind << ": carriers must be shadowed for it to mean something";
  }
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// 2,048 robots: two sensing chunks, parallel motion bands.
TEST(QuirksWorld, WorldQuirksAreBitIdenticalForOneAndTwoThreads) {
  for (const char* kind : {"crw", "dpo"}) {
    WorldConfig c =
        withQuirks({Quirk::kRimGroundSensors, Quirk::kBlockPenalties, Quirk::kLightOcclusion}, 2048);
    c.arena.name = "64x32";
    c.arena.width = 64;
    c.arena.height = 32;
    c.arena.n_blocks = 200;
    c.seed = 7;
    Simulation one(c, kind, ControllerConfigs{}, 1), two(c, kind, ControllerConfigs{}, 2);
    uint64_t shadowed = 0;
    for (int t = 0; t < 300; ++t) {
      one.step();
      two.step();
      const RobotBodies &a = one.world().robots(), &b = two.world().robots();
      ASSERT_TRUE(sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.theta, b.theta)) << kind << " " << t;
      ASSERT_TRUE(sameBits(a.carried, b.carried)) << kind << " tick " << t;
      ASSERT_TRUE(sameBits(one.sensors().light_x, two.sensors().light_x)) << kind << " tick " << t;
      ASSERT_TRUE(sameBits(one.sensors().ground, two.sensors().ground)) << kind << " tick " << t;
      ASSERT_EQ(one.world().shadowedLights(), two.world().shadowedLights());
      shadowed += one.world().shadowedLights();
    }
    EXPECT_EQ(one.world().delivered(), two.world().delivered());
    EXPECT_GT(shadowed, 0u) << kind << ": occlusion must happen for the comparison to mean something";
  }
}

}  // namespace
}  // namespace swarm_forage
