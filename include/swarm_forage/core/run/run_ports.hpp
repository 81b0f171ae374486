#pragma once
// The three ports of the run engine (docs/design.md, One run engine): where commands come from (controller
// batches in process, or the lockstep barrier over topics), where the condition comes from (in process, or
// the throttle topic), and where records go (a bag, topics, or nowhere).
#include <optional>
#include <string>
#include <vector>

#include "swarm_forage/core/run/run_records.hpp"
#include "swarm_forage/core/util/state_archive.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

/// What a step of a run came to: ok (the run goes on; for the whole run, it got to its last tick), or
/// stopped with the reason, which names who, what and when. A type, so that success is never an empty string.
class StepOutcome {
 public:
  static StepOutcome ok() { return StepOutcome(); }
  static StepOutcome stop(std::string reason) { return StepOutcome(std::move(reason)); }
  bool stopped() const { return stopped_; }
  const std::string& reason() const { return reason_; }

 private:
  StepOutcome() = default;
  explicit StepOutcome(std::string reason) : stopped_(true), reason_(std::move(reason)) {}
  bool stopped_ = false;
  std::string reason_;
};

class ControllerPort {
 public:
  virtual ~ControllerPort() = default;
  /// A new run (tick 0 next) in `world`.
  virtual void begin(const RunDescription& run, const World& world) = 0;
  /// The commands and status for `tick` from its readings: ok once they are in, else why the run cannot
  /// go on (a controller that does not answer, ranges that do not fit together, ...).
  virtual StepOutcome decide(uint64_t tick, const World& world, const SensorData& sensors) = 0;
  /// The commands the world steps with: the whole swarm's.
  virtual const CommandData& commands() const = 0;
  /// This tick's status, one record per controller range, in first-id order.
  virtual const std::vector<StatusRecord>& status() const = 0;
  /// Checkpoints (Run::checkpoint): the constants the controllers report at tick 0 (after begin()), and
  /// their state saved or loaded between two ticks. By default they cannot be checkpointed.
  virtual std::string constants() const { return ""; }
  virtual void persist(StateArchive& /*a*/) {
    throw CheckpointError("the controllers of this run cannot be checkpointed");
  }
};

class EnvironmentPort {
 public:
  virtual ~EnvironmentPort() = default;
  /// The condition for `tick`, asked once its controllers have decided; none: no environment (V = 0).
  virtual std::optional<ConditionSample> condition(uint64_t tick) = 0;
};

/// No environment: V = 0 throughout (an ideal run whose record names no waveform).
class NoEnvironment : public EnvironmentPort {
 public:
  std::optional<ConditionSample> condition(uint64_t) override { return std::nullopt; }
};

/// Where a run's records go. A record (a bag) gets the record schedule; a live view (topics) gets
/// snapshots at its own pace and neither status nor condition (other nodes publish those).
class RunSink {
 public:
  virtual ~RunSink() = default;
  virtual bool isRecord() const = 0;
  /// Whether a due snapshot is wanted now (a live view nobody watches: no).
  virtual bool wantsSnapshot() const { return true; }
  /// Tick 0, before anything else: the nest and what made the run (model version, code, `label`).
  virtual void begin(const RunDescription& run, const std::string& label) = 0;
  /// Robots and blocks at `tick` (carried blocks at their carrier).
  virtual void snapshot(uint64_t tick, const SensorData& sensors, const BlockField& blocks) = 0;
  /// The cache at `tick`: at tick 0 and whenever it appears, vanishes or changes its block count.
  virtual void caches(uint64_t tick, const StaticCache& cache) = 0;
  /// The run's description once tick 0 has fixed its identity.
  virtual void identityFixed(const RunDescription& run) = 0;
  /// Records only, after the step of `tick`: the condition, when conditionChanged().
  virtual void condition(uint64_t /*tick*/, const ConditionSample&) {}
  /// After each step of a run with population dynamics, before stepped(): the population and its events.
  virtual void population(const PopulationRecord&) {}
  /// The sensor and actuator noise changed by hand, in force from `tick` on (Run::changeNoise).
  virtual void noiseChanged(uint64_t /*tick*/, const SaaNoise& /*noise*/) {}
  /// After each step: the tick's status (records only) and performance.
  virtual void stepped(const std::vector<StatusRecord>& status, const PerformanceRecord& performance) = 0;
  /// How the run ended, records first: a record closes and sets `end.bag` (and, when its name cannot be
  /// taken, makes the run incomplete with the reason); a live view announces it.
  virtual void end(RunEndRecord& end) = 0;
  /// Checkpoints (Run::checkpoint): saves what the sink must keep to go on as if the run never stopped
  /// (a bag: its messages so far), after the records of the tick just stepped.
  virtual void save(StateArchive& /*a*/) {}
  /// A resumed run, instead of begin(): reads what save() wrote, for the fixed description `run` at tick
  /// `tick`. A fork (another condition, Run::resume) gives `fork`: the condition records a fresh run of
  /// `run` would have made before `tick`; the sink's records must then be those of that fresh run.
  virtual void resume(StateArchive& /*a*/, const RunDescription& /*run*/, uint64_t /*tick*/,
                      const std::vector<ConditionSample>* /*fork*/) {}
};

/// Appends how each run ended to a YAML list file (appendOutcome); throws std::runtime_error when it
/// cannot. Last among the sinks: the end names the bag.
class OutcomeFile : public RunSink {
 public:
  explicit OutcomeFile(std::string path) : path_(std::move(path)) {}
  bool isRecord() const override { return false; }
  bool wantsSnapshot() const override { return false; }
  void begin(const RunDescription&, const std::string&) override {}
  void snapshot(uint64_t, const SensorData&, const BlockField&) override {}
  void caches(uint64_t, const StaticCache&) override {}
  void identityFixed(const RunDescription&) override {}
  void stepped(const std::vector<StatusRecord>&, const PerformanceRecord&) override {}
  void end(RunEndRecord& end) override;

 private:
  std::string path_;
};

}  // namespace swarm_forage
