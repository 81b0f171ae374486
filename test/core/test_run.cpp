// The run engine: what it records when, how a run ends, and its identity and bag name.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "swarm_forage/core/run/in_process.hpp"
#include "swarm_forage/core/run/run.hpp"

namespace swarm_forage {
namespace {

/// Writes what it is given as one line per record ("snapshot 0", "info", ...).
class Log : public RunSink {
 public:
  explicit Log(bool record) : record_(record) {}
  bool isRecord() const override { return record_; }
  void begin(const RunDescription&, const std::string& label) override { lines.push_back("begin " + label); }
  void snapshot(uint64_t tick, const SensorData&, const BlockField&) override {
    lines.push_back("snapshot " + std::to_string(tick));
  }
  void caches(uint64_t tick, const StaticCache&) override {
    lines.push_back("caches " + std::to_string(tick));
  }
  void identityFixed(const RunDescription& run) override { lines.push_back("info " + run.identity()); }
  void condition(uint64_t tick, const ConditionSample&) override {
    lines.push_back("condition " + std::to_string(tick));
  }
  void stepped(const std::vector<StatusRecord>& status, const PerformanceRecord& p) override {
    lines.push_back("status " + std::to_string(status.size()) + " performance " + std::to_string(p.tick) +
                    (p.last ? " last" : ""));
  }
  void end(RunEndRecord& end) override {
    lines.push_back("end " + std::string(end.complete ? "complete" : end.reason));
    if (record_) end.bag = "recorded";
  }
  std::vector<std::string> lines;

 private:
  bool record_;
};

RunDescription smallRun(const std::string& controller, uint64_t ticks) {
  RunDescription d;
  d.controller = controller;
  d.world.n_robots = 4;
  d.world.seed = 3;
  d.ticks = ticks;
  return d;
}

TEST(Run, RecordsOnItsSchedule) {
  auto pool = std::make_shared<WorkerPool>(1);
  InProcessControllers controllers({}, pool);
  Condition step;
  step.waveform = "step_down";
  step.beta = 0.5;
  step.alpha = 0.4;  // tick 2 at 5 ticks per second: V changes there
  InProcessEnvironment environment(step, 5.0);
  Log bag(true), topics(false);
  swarm_forage::Run run(smallRun("crw", 5), RunSchedule{2, 4}, pool, controllers, environment,
                        {&topics, &bag}, "L");
  const RunEndRecord end = run.execute(nullptr);
  EXPECT_TRUE(end.complete);
  EXPECT_EQ(end.ticks_done, 5u);
  EXPECT_EQ(end.bag, "recorded");  // the record closed before the live view heard of the end
  EXPECT_EQ(end.identity, run.description().identity());
  EXPECT_EQ(end.identity.size(), 8u);
  const std::vector<std::string> recorded = {"begin L",
                                             "snapshot 0",
                                             "info " + end.identity,
                                             "condition 0",
                                             "status 1 performance 0",
                                             "status 1 performance 1",
                                             "snapshot 2",
                                             "condition 2",
                                             "status 1 performance 2",
                                             "condition 3",
                                             "status 1 performance 3",
                                             "snapshot 4",
                                             "status 1 performance 4 last",
                                             "end complete"};
  EXPECT_EQ(bag.lines, recorded);
  const std::vector<std::string> live = {"begin L",
                                         "snapshot 0",
                                         "info " + end.identity,
                                         "status 1 performance 0",
                                         "status 1 performance 1",
                                         "status 1 performance 2",
                                         "status 1 performance 3",
                                         "snapshot 4",
                                         "status 1 performance 4 last",
                                         "end complete"};
  EXPECT_EQ(topics.lines, live);
}

TEST(Run, StopsWithTheReasonAndNoIdentityBeforeTickZero) {
  auto pool = std::make_shared<WorkerPool>(1);
  InProcessControllers controllers({}, pool);
  NoEnvironment none;
  Log bag(true);
  swarm_forage::Run early(smallRun("crw", 10), {}, pool, controllers, none, {&bag}, "");
  RunEndRecord end =
      early.execute([](uint64_t tick) { return tick == 0 ? StepOutcome::stop("stop") : StepOutcome::ok(); });
  EXPECT_FALSE(end.complete);
  EXPECT_EQ(end.reason, "stop");
  EXPECT_EQ(end.identity, "");
  swarm_forage::Run later(smallRun("dpo", 10), {}, pool, controllers, none, {&bag}, "");
  end = later.execute(
      [](uint64_t tick) { return tick == 6 ? StepOutcome::stop("signal") : StepOutcome::ok(); });
  EXPECT_EQ(end.ticks_done, 6u);
  EXPECT_EQ(end.reason, "signal");
  EXPECT_EQ(end.identity, later.description().identity());
  EXPECT_FALSE(end.identity.empty());
}

TEST(Run, NamesItsBagByWhatIsKnown) {
  RunDescription d = smallRun("crw", 100);
  d.world.arena.name = "32x16";
  d.run = 2;
  EXPECT_EQ(runBagName(d), "crw_32x16_n4_seed3_run2.bag");
  EXPECT_EQ(runBagPath("/t/a.bag", "", d), "/t/a_run2.bag");
  d.run = 0;
  EXPECT_EQ(runBagPath("/t/a.bag", "", d), "/t/a.bag");
  d.fixed = true;
  d.world.quirks = FordycaQuirks::parse("fordyca_2019", "");  // the default model: no model word
  Condition step;
  step.waveform = "step_down";
  step.beta = 0.4;
  step.alpha = 5;
  d.condition = conditionAt(step, 0, 5.0);
  EXPECT_EQ(runBagPath("", "/t", d), "/t/crw_32x16_n4_step_down0.4_seed3_" + d.identity() + ".bag");
  // The seed and the run number are not part of the identity.
  RunDescription other = d;
  other.world.seed = 9;
  other.run = 4;
  EXPECT_EQ(other.identity(), d.identity());
  other.controller_constants = "crw/x=1";
  EXPECT_NE(other.identity(), d.identity());
  // What varies beside the condition is in the name too: noise, population dynamics, the model.
  RunDescription varied = d;
  varied.world.noise.proximity.level = varied.world.noise.light.level = varied.world.noise.position.level =
      varied.world.noise.heading.level = varied.world.noise.wheels.level = varied.world.noise.ground = 0.03;
  EXPECT_EQ(runBagName(varied),
            "crw_32x16_n4_step_down0.4_saa-all-gaussian0.03_seed3_" + varied.identity() + ".bag");
  varied.world.noise = SaaNoise();
  varied.world.noise.light = {NoiseModel::kUniform, 0.02};
  varied.world.noise.ground = 0.05;
  varied.world.population.death = 0.005;
  varied.world.population.repair = 0.004;
  varied.world.quirks = FordycaQuirks::parse("fordyca_2019", "dynamics2d_contacts");
  EXPECT_EQ(runBagName(varied),
            "crw_32x16_n4_step_down0.4_saa-light-uniform0.02-ground0.05_pd-d0.005-r0.004_"
            "dynamics2d_contacts_seed3_" +
                varied.identity() + ".bag");
  varied.world.quirks = FordycaQuirks::parse("swarm_forage", "heading_estimate");
  varied.world.population = PopulationConfig();
  varied.world.noise = SaaNoise();
  EXPECT_EQ(runBagName(varied),
            "crw_32x16_n4_step_down0.4_swarm_forage_heading_estimate_seed3_" + varied.identity() + ".bag");
}

/// Two ranges that each report a controller and its constants at tick 0 (robots stand still): what nodes
/// outside the build (a rospy node, docs/rospy-controller.md) look like to the engine.
class TwoRanges : public ControllerPort {
 public:
  TwoRanges(std::string low, std::string high) : kinds_{std::move(low), std::move(high)} {}
  void begin(const RunDescription&, const World& world) override {
    commands_.resize(world.config().n_robots);
  }
  StepOutcome decide(uint64_t tick, const World& world, const SensorData&) override {
    const uint32_t n = world.config().n_robots, half = n / 2;
    status_.clear();
    for (int k = 0; k < 2; ++k) {
      StatusRecord s;
      s.tick = tick;
      s.first_id = k == 0 ? 0 : half;
      s.count = k == 0 ? half : n - half;
      s.controller = kinds_[k];
      s.constants = tick == 0 ? kinds_[k] + "/x=1" : "";
      s.source = k == 0 ? "/low" : "/high";
      status_.push_back(s);
    }
    return StepOutcome::ok();
  }
  const CommandData& commands() const override { return commands_; }
  const std::vector<StatusRecord>& status() const override { return status_; }

 private:
  std::string kinds_[2];
  CommandData commands_;
  std::vector<StatusRecord> status_;
};

TEST(Run, AnExternalControllerIsNamedAndHeldInTheIdentity) {
  auto pool = std::make_shared<WorkerPool>(1);
  NoEnvironment none;
  RunDescription mixed = smallRun("crw", 3);
  mixed.external = "numpy_forager";
  TwoRanges both("crw", "numpy_forager");
  swarm_forage::Run run(mixed, {}, pool, both, none, {}, "");
  EXPECT_TRUE(run.execute(nullptr).complete);
  EXPECT_EQ(run.description().name(), "crw+numpy_forager");
  EXPECT_EQ(run.description().key().controller, "crw+numpy_forager");
  EXPECT_EQ(run.description().controller_constants, "crw/x=1 numpy_forager/x=1");  // the announced kind first
  EXPECT_EQ(runBagName(run.description()).rfind("crw_numpy_forager_", 0), 0u);

  // Alone, it needs nothing of the world: no line of sight, no cache, whatever the configuration said.
  RunDescription alone = smallRun("numpy_forager", 3);
  alone.external = "numpy_forager";
  alone.world.line_of_sight = true;
  TwoRanges external("numpy_forager", "numpy_forager");
  swarm_forage::Run run_alone(alone, {}, pool, external, none, {}, "");
  EXPECT_FALSE(run_alone.description().world.line_of_sight);
  EXPECT_TRUE(run_alone.execute(nullptr).complete);
  EXPECT_EQ(run_alone.description().name(), "numpy_forager");
  EXPECT_EQ(run_alone.description().controller_constants, "numpy_forager/x=1");
}

TEST(Run, RefusesAControllerItWasNotToldOfAtTickZero) {
  auto pool = std::make_shared<WorkerPool>(1);
  NoEnvironment none;
  TwoRanges both("crw", "numpy_forager");
  swarm_forage::Run undeclared(smallRun("crw", 3), {}, pool, both, none, {}, "");
  EXPECT_EQ(undeclared.execute(nullptr).reason,
            "tick 0: /high [2, 4) runs controller 'numpy_forager', but the run is crw (~controller)");
  RunDescription mixed = smallRun("crw", 3);
  mixed.external = "numpy_forager";
  TwoRanges crw_only("crw", "crw");
  swarm_forage::Run unserved(mixed, {}, pool, crw_only, none, {}, "");
  EXPECT_EQ(unserved.execute(nullptr).reason,
            "tick 0: no node runs controller numpy_forager of the run crw+numpy_forager (~controller, "
            "~external_controller); every range runs crw: /low [0, 2), /high [2, 4)");
}

}  // namespace
}  // namespace swarm_forage
