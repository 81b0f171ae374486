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
  void fixed(const RunDescription& run) override { lines.push_back("info " + run.identity()); }
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
  RunEndRecord end = early.execute([](uint64_t tick) { return tick == 0 ? "stop" : ""; });
  EXPECT_FALSE(end.complete);
  EXPECT_EQ(end.reason, "stop");
  EXPECT_EQ(end.identity, "");
  swarm_forage::Run later(smallRun("dpo", 10), {}, pool, controllers, none, {&bag}, "");
  end = later.execute([](uint64_t tick) { return tick == 6 ? "signal" : ""; });
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
}

}  // namespace
}  // namespace swarm_forage
