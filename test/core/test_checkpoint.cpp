// Checkpoints (docs/runs-and-bags.md): a run saved after tick K and resumed in new objects records what the
// run that never stopped records, and ends in the same state; forks; broken files are refused.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "sharing_pool.hpp"
#include "swarm_forage/core/controllers/crw.hpp"
#include "swarm_forage/core/run/checkpoint.hpp"
#include "swarm_forage/core/run/in_process.hpp"
#include "swarm_forage/core/run/run.hpp"

namespace swarm_forage {
namespace {

uint64_t digest(uint64_t h, const void* p, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) h = (h ^ static_cast<const unsigned char*>(p)[k]) * 1099511628211ULL;
  return h;
}
template <typename T>
uint64_t digest(uint64_t h, const std::vector<T>& v) {
  return digest(h, v.data(), v.size() * sizeof(T));
}

/// Every record as a line of text with a digest of its content; saved and resumed as a bag would be.
class Trace : public RunSink {
 public:
  bool isRecord() const override { return true; }
  void begin(const RunDescription&, const std::string&) override { lines.push_back("begin"); }
  void snapshot(uint64_t tick, const SensorData& s, const BlockField& b) override {
    uint64_t h = digest(digest(digest(1, s.x), s.y), s.theta);
    for (std::size_t k = 0; k < b.size(); ++k) {
      const double xy[2] = {b.x(static_cast<int32_t>(k)), b.y(static_cast<int32_t>(k))};
      const int32_t carrier = b.carrier(static_cast<int32_t>(k));
      h = digest(digest(h, xy, sizeof xy), &carrier, sizeof carrier);
    }
    lines.push_back("snapshot " + std::to_string(tick) + " " + std::to_string(h));
  }
  void caches(uint64_t tick, const StaticCache& c) override {
    lines.push_back("cache " + std::to_string(tick) + " " + std::to_string(c.exists()) + " " +
                    std::to_string(c.size()));
  }
  void identityFixed(const RunDescription& run) override { lines.push_back("info " + run.identity()); }
  void condition(uint64_t tick, const ConditionSample& c) override {
    lines.push_back(conditionLine(tick, c));
  }
  void population(const PopulationRecord& r) override {
    uint64_t h = digest(digest(digest(digest(1, r.deaths), r.births), r.malfunctions), r.repairs);
    lines.push_back("population " + std::to_string(r.tick) + " " + std::to_string(r.active) + " " +
                    std::to_string(r.queue) + " " + std::to_string(h));
  }
  void stepped(const std::vector<StatusRecord>& status, const PerformanceRecord& p) override {
    std::string line = "step " + std::to_string(p.tick) + " " + std::to_string(p.delivered) + " " +
                       std::to_string(p.cumulative) + " " + std::to_string(p.carrying) + " " +
                       std::to_string(p.throttle);
    for (const StatusRecord& s : status) {
      line += " | " + std::to_string(s.status.in_avoidance) + " " + std::to_string(s.status.stalled) + " " +
              std::to_string(digest(1, s.status.state_counts)) + " " + s.constants;
    }
    lines.push_back(line);
  }
  void end(RunEndRecord& end) override {
    lines.push_back("end " + std::to_string(end.ticks_done) + " " + end.identity + " " + end.reason);
  }
  void save(StateArchive& a) override {
    a.section("trace");
    a.io(lines);
  }
  void resume(StateArchive& a, const RunDescription& run, uint64_t,
              const std::vector<ConditionSample>* fork) override {
    a.section("trace");
    a.io(lines);
    if (!fork) return;
    std::size_t next = 0;  // a fork's records are a fresh run's: its run info and condition records
    for (std::string& line : lines) {
      if (line.rfind("info ", 0) == 0) line = "info " + run.identity();
      if (line.rfind("condition ", 0) == 0) line = conditionLine((*fork)[next].tick, (*fork)[next]), ++next;
    }
    EXPECT_EQ(next, fork->size());
  }
  static std::string conditionLine(uint64_t tick, const ConditionSample& c) {
    return "condition " + std::to_string(tick) + " " + std::to_string(c.value) + " " + c.condition.label();
  }
  std::vector<std::string> lines;
};

struct Case {
  std::string controller = "crw";
  uint32_t n = 64;
  uint64_t ticks = 3000;  // 10 simulated minutes: blocks are delivered before and after the checkpoint
  bool delivers = true;
  Condition condition;
  std::function<void(WorldConfig&)> world;
  unsigned threads = 1;
};

/// One run's objects; `stop_at`: interrupted before that tick, with a checkpoint after the tick before.
struct Running {
  explicit Running(const Case& s)
      : pool(sharingPool(s.threads)),
        controllers({}, pool),
        environment(s.condition.forRun(s.ticks, 5.0), 5.0) {
    RunDescription d;
    d.controller = s.controller;
    d.world.n_robots = s.n;
    d.world.seed = 7;
    d.world.ticks_per_second = 5.0;
    if (s.world) s.world(d.world);
    d.ticks = s.ticks;
    run = std::make_unique<Run>(d, RunSchedule{50, 50}, pool, controllers, environment,
                                std::vector<RunSink*>{&trace}, "test");
  }
  std::shared_ptr<WorkerPool> pool;
  InProcessControllers controllers;
  InProcessEnvironment environment;
  Trace trace;
  std::unique_ptr<Run> run;
};

Condition waveform(const std::string& name, double beta = 0, double alpha = 0) {
  Condition c;
  c.waveform = name;
  c.beta = beta;
  c.alpha = alpha;
  return c;
}

/// The payload of a checkpoint after tick k of `s` (the run stopped there).
std::string checkpointAt(const Case& s, uint64_t k) {
  Running r(s);
  std::string payload;
  r.run->setAfterStep([&](uint64_t done) {
    if (done == k) payload = r.run->checkpoint();
  });
  const RunEndRecord end = r.run->execute(
      [k](uint64_t tick) { return tick == k ? StepOutcome::stop("stop") : StepOutcome::ok(); });
  EXPECT_EQ(end.ticks_done, k);
  return payload;
}

/// `s` run through, and `s` saved after tick k and resumed in new objects (with `resumed_threads`) record
/// the same and end in the same state (their final checkpoints are equal byte for byte).
void expectResumeEqual(const Case& s, uint64_t k, unsigned resumed_threads = 2) {
  Running whole(s);
  whole.run->execute(nullptr);
  const std::string payload = checkpointAt(s, k);
  Case later = s;
  later.threads = resumed_threads;
  Running resumed(later);
  resumed.run->resume(payload, "memory");
  resumed.run->execute(nullptr);
  ASSERT_EQ(resumed.trace.lines.size(), whole.trace.lines.size());
  for (std::size_t i = 0; i < whole.trace.lines.size(); ++i)
    ASSERT_EQ(resumed.trace.lines[i], whole.trace.lines[i]) << "record " << i;
  EXPECT_EQ(resumed.run->checkpoint(), whole.run->checkpoint());
  if (s.delivers) {
    EXPECT_GT(whole.run->world().delivered(), 0u) << "a run that delivers nothing tests little";
  }
}

TEST(Checkpoint, CrwResumesBitIdentical) { expectResumeEqual(Case{}, 1500); }

TEST(Checkpoint, CrwResumesOnOneThreadFromFour) {
  Case s;
  s.threads = 4;
  s.n = 1024;  // parts of 512 robots: the checkpoint is written by several batches, read by one
  s.ticks = 200;
  s.delivers = false;
  expectResumeEqual(s, 101, 1);
}

TEST(Checkpoint, DpoResumesBitIdentical) {
  Case s;
  s.controller = "dpo";
  expectResumeEqual(s, 1250);
}

TEST(Checkpoint, GpDpoResumesBitIdentical) {
  Case s;
  s.controller = "gp_dpo";
  expectResumeEqual(s, 1777);
}

TEST(Checkpoint, ResumesUnderConditionNoiseAndPopulation) {
  Case s;
  s.controller = "dpo";
  s.condition = waveform("step_up", 0.5, 400.0);  // V changes at tick 2000, after the checkpoint
  s.world = [](WorldConfig& w) {
    w.noise.proximity.level = 0.01;
    w.noise.wheels.level = 0.05;
    w.noise.position.level = 0.01;
    w.noise.ground = 0.02;
    w.population.death = 0.01;
    w.population.birth = 0.01;
    w.population.malfunction = 0.01;
    w.population.repair = 0.02;
  };
  expectResumeEqual(s, 1333);
  s.condition = waveform("step_down", 0.4, 100.0);  // ... and before it
  expectResumeEqual(s, 1333);
}

TEST(Checkpoint, ResumesWithFordycaQuirks) {
  Case s;
  s.controller = "gp_dpo";
  s.world = [](WorldConfig& w) { w.quirks = FordycaQuirks::parse("fordyca_2019", ""); };
  expectResumeEqual(s, 1501);
}

TEST(Checkpoint, ForkEqualsAFreshRunOfItsCondition) {
  Case ideal;
  const uint64_t alpha = 250;  // 50 s at 5 ticks per second
  const std::string payload = checkpointAt(ideal, alpha);
  Case step = ideal;
  step.condition = waveform("step_up", 0.6, 50.0);
  Running fresh(step);
  fresh.run->execute(nullptr);
  Running fork(step);
  fork.run->resume(payload, "memory");
  fork.run->execute(nullptr);
  EXPECT_EQ(fork.trace.lines, fresh.trace.lines);
  EXPECT_EQ(fork.run->description().identity(), fresh.run->description().identity());
  EXPECT_NE(fork.run->description().identity(), Running(ideal).run->description().identity() + "x");
}

TEST(Checkpoint, RefusesAConditionThatIsNoFork) {
  const std::string payload = checkpointAt(Case{}, 250);
  Case early;
  early.condition = waveform("step_up", 0.6, 40.0);  // V rises at tick 200, before the checkpoint
  Running r(early);
  try {
    r.run->resume(payload, "ideal.ckpt");
    FAIL() << "a step before the checkpoint was taken for a fork";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("no fork of ideal.ckpt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("first at tick 200"), std::string::npos) << e.what();
  }
}

TEST(Checkpoint, RefusesAnotherRunNamingWhatDiffers) {
  const std::string payload = checkpointAt(Case{}, 100);
  Case other;
  other.n = 65;
  Running r(other);
  try {
    r.run->resume(payload, "a.ckpt");
    FAIL() << "another swarm size was resumed";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("the checkpoint has N=64 where the parameters give N=65"),
              std::string::npos)
        << e.what();
  }
  // A word only one side has is paired with its absence, not with the next word of the other side.
  Case serialized;
  serialized.world = [](WorldConfig& w) { w.serialize_block_ops = true; };
  Running s(serialized);
  try {
    s.run->resume(payload, "a.ckpt");
    FAIL() << "another world was resumed";
  } catch (const ParameterError& e) {
    EXPECT_NE(
        std::string(e.what()).find(
            "the checkpoint has no serialize_block_ops where the parameters give serialize_block_ops=1"),
        std::string::npos)
        << e.what();
  }
}

TEST(Checkpoint, FileRefusesTruncationCorruptionAndOtherFiles) {
  const std::string payload = checkpointAt(Case{}, 50);
  const std::string path = ::testing::TempDir() + "/test_checkpoint.ckpt";
  writeCheckpointFile(path, payload);
  EXPECT_EQ(readCheckpointFile(path), payload);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto refused = [&](const std::string& content, const std::string& why) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << content;
    try {
      readCheckpointFile(path);
      ADD_FAILURE() << "read a file that is " << why;
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  refused(bytes.substr(0, bytes.size() / 2), "truncated");
  std::string flipped = bytes;
  flipped[flipped.size() / 2] ^= 0x10;
  refused(flipped, "corrupted");
  refused("ROSBAG V2.0\n", "not a swarm_forage checkpoint");
  std::remove(path.c_str());
  // A payload cut short inside the state is refused too (not read past its end).
  Running r{Case{}};
  EXPECT_THROW(r.run->resume(payload.substr(0, payload.size() - 100), "cut"), CheckpointError);
}

/// A kind that keeps state the built-ins do not know of: it must not be checkpointed as a plain CRW.
class CrwWithMore : public CrwBatch {
 public:
  using CrwBatch::CrwBatch;
};

TEST(Checkpoint, OnlyKindsThatSaveEverythingAreCheckpointable) {
  CrwBatch crw(CrwConfig{}, 1, 0, 4);
  EXPECT_TRUE(crw.checkpointable());
  CrwWithMore derived(CrwConfig{}, 1, 0, 4);
  EXPECT_FALSE(derived.checkpointable());
  StateArchive a;
  EXPECT_THROW(derived.persist(a), CheckpointError);
}

}  // namespace
}  // namespace swarm_forage
