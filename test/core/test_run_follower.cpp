// RunFollower: one tick's performance and status ranges joined in any order, live (joins late, counts a
// dead node's ticks with what arrived, closes a cut run short) and as a record (whole, or why not).
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/run_follower.hpp"

namespace swarm_forage {
namespace {

constexpr uint32_t kRobots = 4;

struct Log : RunFollower::Listener {
  std::vector<IntervalSample> samples;
  std::vector<uint64_t> stamps;  // of each sample
  std::vector<JoinedTick> ticks;
  std::vector<std::string> notes;
  int described_runs = 0;
  void described(const FollowedRun&) override { ++described_runs; }
  void counted(const FollowedRun&, const JoinedTick& t) override { ticks.push_back(t); }
  void sample(const FollowedRun&, const IntervalSample& s, uint64_t stamp_ns) override {
    samples.push_back(s);
    stamps.push_back(stamp_ns);
  }
  void warn(const std::string& w) override { notes.push_back(w); }
  void error(const std::string& e) override { notes.push_back(e); }
};

AnnouncedRun description(uint64_t ticks, const std::string& waveform = "null") {
  AnnouncedRun d;
  d.key.controller = "crw";
  d.key.swarm_size = kRobots;
  d.key.setup.ticks = ticks;
  d.key.environment.waveform = waveform;
  d.seed = 3;
  return d;
}
PerformanceRecord perf(uint64_t tick, uint64_t ticks, uint32_t run = 0) {
  PerformanceRecord p;
  p.run = run;
  p.swarm_size = kRobots;
  p.tick = tick;
  p.delivered = tick % 2;
  p.cumulative = (tick + 1) / 2;
  p.last = tick + 1 == ticks;
  return p;
}
StatusRecord range(uint64_t tick, uint32_t first, uint32_t count, uint32_t in_avoidance, uint32_t run = 0) {
  StatusRecord s;
  s.tick = tick;
  s.run = run;
  s.first_id = first;
  s.count = count;
  s.swarm_size = kRobots;
  s.status.in_avoidance = in_avoidance;
  s.source = "/controller_" + std::to_string(first);
  return s;
}
/// A tick's stamp (ns): the follower hands it back with the samples the tick closes.
uint64_t stamp(uint64_t tick) { return 1000 + 10 * tick; }
/// The messages of ticks [from, until) of a run of `ticks` ticks: status in two ranges, before the
/// performance on odd ticks.
void feedRun(RunFollower& f, uint64_t ticks, uint64_t from = 0, uint64_t until = 0) {
  for (uint64_t t = from; t < (until ? until : ticks); ++t) {
    if (t % 2) f.status(range(t, 0, 2, 1));
    f.performance(perf(t, ticks), stamp(t));
    if (t % 2 == 0) f.status(range(t, 0, 2, 1));
    f.status(range(t, 2, 2, t % 3 == 0 ? 2 : 0));
  }
}
RunEndRecord ended(uint64_t ticks, bool complete = true) {
  RunEndRecord e;
  e.ticks_done = e.ticks = ticks;
  e.complete = complete;
  return e;
}

TEST(RunFollower, JoinsEachTickInAnyOrderIntoTheSameSeriesAsTheBuilder) {
  Log log;
  RunFollower f(3, RunFollower::Mode::kLive, &log);
  f.describe(0, description(7));
  feedRun(f, 7);
  RunSeriesBuilder direct(3, kRobots);
  for (uint64_t t = 0; t < 7; ++t) direct.add(t, t % 2, (t + 1) / 2, 1 + (t % 3 == 0 ? 2 : 0), t == 6, 0.0);
  ASSERT_EQ(log.samples.size(), 3u);  // ticks 0-2, 3-5 and the short final 6
  EXPECT_EQ(log.stamps, (std::vector<uint64_t>{stamp(2), stamp(5), stamp(6)}));
  EXPECT_TRUE(log.samples.back().final);
  EXPECT_EQ(f.run()->builder->series().n_ca, direct.series().n_ca);
  EXPECT_EQ(f.run()->builder->series().P, direct.series().P);
  ASSERT_EQ(log.ticks.size(), 7u);
  EXPECT_EQ(log.ticks[3].in_avoidance, 3u);
  EXPECT_EQ(log.ticks[3].covered, kRobots);
  EXPECT_EQ(log.ticks[3].ranges, 2u);
  EXPECT_EQ(log.described_runs, 1);
  EXPECT_TRUE(log.notes.empty());
}

TEST(RunFollower, LiveWaitsForTheRunsDescriptionAndJoinsLate) {
  Log log;
  RunFollower f(2, RunFollower::Mode::kLive, &log);
  feedRun(f, 6, 2);
  EXPECT_TRUE(log.ticks.empty());
  EXPECT_EQ(f.waiting(), 4u);
  f.describe(0, description(6));
  EXPECT_EQ(log.ticks.size(), 4u);
  EXPECT_EQ(log.ticks.front().performance.tick, 2u);
  ASSERT_FALSE(log.notes.empty());
  EXPECT_NE(log.notes[0].find("joined run 0 at tick 2"), std::string::npos);
}

TEST(RunFollower, LiveFlushCountsWhatArrivedAndClosesACutRunShort) {
  Log log;
  RunFollower f(4, RunFollower::Mode::kLive, &log);
  f.describe(0, description(100));
  feedRun(f, 100, 0, 6);                  // a run of 100 ticks cut after tick 5 ...
  f.performance(perf(6, 100), stamp(6));  // ... whose tick 6 lacks its status
  EXPECT_EQ(log.samples.size(), 1u);
  f.flush();
  ASSERT_EQ(log.samples.size(), 2u);
  EXPECT_EQ(log.samples[1].tick_end, 6u);
  EXPECT_EQ(log.samples[1].interval_ticks, 3u);
  EXPECT_FALSE(log.samples[1].final);
  EXPECT_EQ(log.ticks.back().covered, 0u);
  EXPECT_NE(log.notes.back().find("tick 6 never completed"), std::string::npos);
}

TEST(RunFollower, LiveFollowsAWorldStartedAfreshFromTickZero) {
  Log log;
  RunFollower f(2, RunFollower::Mode::kLive, &log);
  f.describe(0, description(4));
  feedRun(f, 4, 0, 3);  // run 0 interrupted before its last tick
  f.describe(0, description(4));
  feedRun(f, 4);
  ASSERT_FALSE(log.notes.empty());
  EXPECT_NE(log.notes[0].find("a world started run 0 from tick 0"), std::string::npos);
  EXPECT_TRUE(f.run()->finished);
  EXPECT_EQ(f.run()->ticks_seen, 4u);
}

TEST(RunFollower, RecordIsTheWholeRun) {
  RunFollower f(3, RunFollower::Mode::kRecord);
  f.describe(0, description(7));
  feedRun(f, 7);
  f.end(ended(7));
  const RunRecord r = f.record("a.bag");
  EXPECT_EQ(r.seed, 3u);
  EXPECT_EQ(r.series.P.size(), 3u);
  EXPECT_EQ(r.source, "a.bag");
}

std::string recordProblem(RunFollower& f) {
  try {
    f.record("a.bag");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(RunFollower, RecordSaysWhyARunIsNone) {
  {
    RunFollower f(3, RunFollower::Mode::kRecord);
    feedRun(f, 7);
    EXPECT_NE(recordProblem(f).find("no world/run_info"), std::string::npos);
  }
  {
    RunFollower f(3, RunFollower::Mode::kRecord);
    f.describe(0, description(7));
    feedRun(f, 7);
    EXPECT_NE(recordProblem(f).find("no world/run_end"), std::string::npos);
    f.end(ended(7, false));
    EXPECT_NE(recordProblem(f).find("incomplete: run 0 stopped at tick 7 of 7"), std::string::npos);
  }
  {
    RunFollower f(3, RunFollower::Mode::kRecord);
    f.describe(0, description(7));
    for (uint64_t t = 0; t < 7; ++t) {
      if (t == 2) continue;
      f.performance(perf(t, 7), stamp(t));
      f.status(range(t, 0, 4, 0));
    }
    f.end(ended(7));
    EXPECT_EQ(recordProblem(f), "ticks 2 to 2 are missing");
  }
  {
    RunFollower f(3, RunFollower::Mode::kRecord);
    f.describe(0, description(7));
    for (uint64_t t = 0; t < 7; ++t) {
      f.performance(perf(t, 7), stamp(t));
      f.status(range(t, 0, t == 4 ? 2 : 4, 0));
    }
    f.end(ended(7));
    EXPECT_EQ(recordProblem(f), "tick 4: swarm/status covers 2 of 4 robots");
  }
  {
    RunFollower f(3, RunFollower::Mode::kRecord);
    f.describe(0, description(7, "step_down"));
    feedRun(f, 7, 0, 3);
    Condition changed;
    changed.waveform = "step_down";
    changed.beta = 0.5;
    f.condition(ConditionSample{3, 0.5, changed, 0});
    feedRun(f, 7, 3);
    f.end(ended(7));
    EXPECT_NE(recordProblem(f).find("changed live at tick 3"), std::string::npos);
  }
  {  // population rates changed by hand (world/population `changed`): no reference either
    RunFollower f(3, RunFollower::Mode::kRecord);
    f.describe(0, description(7));
    feedRun(f, 7, 0, 3);
    f.populationChanged(1, 3);  // another run's: ignored
    f.populationChanged(0, 4);
    feedRun(f, 7, 3);
    f.end(ended(7));
    EXPECT_NE(recordProblem(f).find("population rates were changed live at tick 4"), std::string::npos);
  }
}

}  // namespace
}  // namespace swarm_forage
