// The run engine refuses commands the world cannot step: a NaN or infinite wheel speed, an unknown request
// code. The run stops at that tick with the controller, its node, the robot and the valid range named.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "swarm_forage/core/run/run.hpp"

namespace swarm_forage {
namespace {

/// Two ranges of crw (nodes /low and /high) that drive straight, and at tick `at` let `spoil` change the
/// commands: what a controller node or rospy node sends, as the world gathers it.
class SpoilingRanges : public ControllerPort {
 public:
  SpoilingRanges(uint64_t at, std::function<void(CommandData&)> spoil) : at_(at), spoil_(std::move(spoil)) {}
  void begin(const RunDescription&, const World& world) override {
    commands_.resize(world.config().n_robots);
  }
  StepOutcome decide(uint64_t tick, const World& world, const SensorData&) override {
    const uint32_t n = world.config().n_robots, half = n / 2;
    std::fill(commands_.left.begin(), commands_.left.end(), 0.05f);
    std::fill(commands_.right.begin(), commands_.right.end(), 0.05f);
    std::fill(commands_.request.begin(), commands_.request.end(), kNone);
    if (tick == at_) spoil_(commands_);
    status_.clear();
    for (int k = 0; k < 2; ++k) {
      StatusRecord s;
      s.tick = tick;
      s.first_id = k == 0 ? 0 : half;
      s.count = k == 0 ? half : n - half;
      s.controller = "crw";
      s.constants = tick == 0 ? "crw/x=1" : "";
      s.source = k == 0 ? "/low" : "/high";
      status_.push_back(s);
    }
    return StepOutcome::ok();
  }
  const CommandData& commands() const override { return commands_; }
  const std::vector<StatusRecord>& status() const override { return status_; }

 private:
  uint64_t at_;
  std::function<void(CommandData&)> spoil_;
  CommandData commands_;
  std::vector<StatusRecord> status_;
};

/// Counts the ticks recorded and keeps how the run ended.
class Ends : public RunSink {
 public:
  bool isRecord() const override { return true; }
  void begin(const RunDescription&, const std::string&) override {}
  void snapshot(uint64_t, const SensorData&, const BlockField&) override {}
  void caches(uint64_t, const StaticCache&) override {}
  void identityFixed(const RunDescription&) override {}
  void stepped(const std::vector<StatusRecord>&, const PerformanceRecord&) override { ++stepped_ticks; }
  void end(RunEndRecord& e) override { ended = e; }
  uint64_t stepped_ticks = 0;
  RunEndRecord ended;
};

struct Outcome {
  RunEndRecord end;
  uint64_t stepped = 0;
  bool poses_finite = true;
};

Outcome runWith(uint64_t at, std::function<void(CommandData&)> spoil) {
  RunDescription d;
  d.controller = "crw";
  d.world.n_robots = 16;
  d.world.seed = 5;
  d.ticks = 10;
  auto pool = std::make_shared<WorkerPool>(1);
  SpoilingRanges controllers(at, std::move(spoil));
  NoEnvironment none;
  Ends record;
  swarm_forage::Run run(d, {}, pool, controllers, none, {&record}, "");
  Outcome o;
  o.end = run.execute(nullptr);
  EXPECT_EQ(record.ended.reason, o.end.reason);  // the record was told
  o.stepped = record.stepped_ticks;
  for (std::size_t i = 0; i < run.world().robots().size(); ++i)
    o.poses_finite = o.poses_finite && std::isfinite(run.world().robots().x[i]) &&
                     std::isfinite(run.world().robots().y[i]) && std::isfinite(run.world().robots().theta[i]);
  return o;
}

void expectStopped(const Outcome& o, uint64_t tick, const std::vector<std::string>& parts) {
  EXPECT_FALSE(o.end.complete);
  EXPECT_EQ(o.end.ticks_done, tick);
  EXPECT_EQ(o.stepped, tick);  // nothing of the bad tick was stepped or recorded
  EXPECT_TRUE(o.poses_finite);
  EXPECT_FALSE(o.end.identity.empty());  // tick 0 fixed it before the check
  for (const std::string& part : parts) EXPECT_NE(o.end.reason.find(part), std::string::npos) << o.end.reason;
}

TEST(RunCommands, ANanWheelSpeedStopsTheRunAtItsTick) {
  const Outcome o = runWith(4, [](CommandData& c) { c.left[11] = std::numeric_limits<float>::quiet_NaN(); });
  expectStopped(o, 4,
                {"controller 'crw' (node /high, robots [8, 16))", "left wheel speed nan", "robot 11",
                 "at tick 4", "valid: a finite number of m/s (the world clamps it to [-0.1, 0.1])"});
}

TEST(RunCommands, AnInfiniteWheelSpeedStopsTheRunAtItsTick) {
  const Outcome o = runWith(0, [](CommandData& c) { c.right[2] = -std::numeric_limits<float>::infinity(); });
  expectStopped(o, 0,
                {"controller 'crw' (node /low, robots [0, 8))", "right wheel speed -inf", "robot 2",
                 "at tick 0", "valid: a finite number"});
}

TEST(RunCommands, AnUnknownRequestCodeStopsTheRunAtItsTick) {
  const Outcome o = runWith(7, [](CommandData& c) { c.request[15] = kCacheDrop + 1; });
  expectStopped(o, 7,
                {"controller 'crw' (node /high, robots [8, 16))", "request code 5", "robot 15", "at tick 7",
                 "valid: 0 to 4 (none, pickup, drop, cache pickup, cache drop)"});
  const Outcome far = runWith(2, [](CommandData& c) { c.request[0] = 255; });
  expectStopped(far, 2, {"node /low", "request code 255", "robot 0", "at tick 2"});
}

TEST(RunCommands, TheFirstOffenderIsNamed) {
  const Outcome o = runWith(3, [](CommandData& c) {
    c.request[12] = 9;
    c.left[5] = std::numeric_limits<float>::infinity();
  });
  expectStopped(o, 3, {"robot 5", "left wheel speed inf"});
}

TEST(RunCommands, LargeFiniteSpeedsAndEveryKnownRequestRun) {
  // The control: what the world can step (it clamps speeds) runs to its end.
  const Outcome o = runWith(3, [](CommandData& c) {
    c.left[1] = std::numeric_limits<float>::max();
    c.right[1] = -1e30f;
    for (uint8_t r = kNone; r <= kCacheDrop; ++r) c.request[r] = r;
  });
  EXPECT_TRUE(o.end.complete) << o.end.reason;
  EXPECT_EQ(o.end.ticks_done, 10u);
  EXPECT_TRUE(o.poses_finite);
}

}  // namespace
}  // namespace swarm_forage
