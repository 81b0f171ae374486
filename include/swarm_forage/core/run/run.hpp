#pragma once
// One run (docs/design.md, One run engine): its start, its tick loop (sense -> decide -> advance), its end
// (complete, or stopped with the reason) and what is recorded when. world_node and run_experiment are
// adapters that give it ports; a run's results do not depend on which.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/run/run_ports.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"

namespace swarm_forage {

/// What goes to sinks when: robots and blocks every `record_every` ticks to records, every
/// `publish_every` to live views; nest and provenance first; run_info at tick 0; the cache and the
/// condition when they change; status and performance every tick; run_end last.
struct RunSchedule {
  uint32_t record_every = 250, publish_every = 25;
};

class Run {
 public:
  /// Builds the world of `description` (with the features its controller needs; throws ParameterError
  /// for an invalid one). The ports and sinks must outlive the run.
  Run(RunDescription description, const RunSchedule& schedule, std::shared_ptr<WorkerPool> pool,
      ControllerPort& controllers, EnvironmentPort& environment, std::vector<RunSink*> sinks,
      std::string label);

  /// `interrupted(tick)`: ok, or why the run must stop before `tick`.
  using Interrupt = std::function<StepOutcome(uint64_t tick)>;
  /// begin(), the ticks, end(): the run's end record. An exception ends the run ("error at tick T: ...")
  /// and is thrown on.
  RunEndRecord execute(const Interrupt& interrupted);
  /// Called after each tick's records with the ticks done so far (run_experiment writes checkpoints there).
  void setAfterStep(std::function<void(uint64_t done)> after) { after_step_ = std::move(after); }

  /// Checkpoints (run_checkpoint.cpp, docs/runs-and-bags.md): the payload of a checkpoint file after the
  /// last tick stepped: the model version, the run without its condition, the condition and a digest of its
  /// V so far, then the state of the world, the controllers, the run and its sinks (a bag: its messages).
  std::string checkpoint();
  /// Continues from a checkpoint's payload: execute() then steps on from its tick instead of beginning.
  /// The parameters must make the checkpointed run (else ParameterError naming the first word that
  /// differs), but for the condition: another one is a fork, allowed when its V (and target) equal the
  /// checkpointed run's in every tick before the checkpoint's (else ParameterError saying where they
  /// differ); its records are then those of a fresh run of its own. `file` names the checkpoint in
  /// messages. CheckpointError: a payload of another model version or state layout.
  void resume(const std::string& payload, const std::string& file);

  /// The tick-0 records (nest, provenance) and the ports' new run.
  void begin();
  /// Steps to the last tick: ok when it got there, else why it stopped.
  StepOutcome steps(const Interrupt& interrupted);
  /// Tells every sink how the run ended (ok: complete); also for a run never begun.
  RunEndRecord end(const StepOutcome& outcome);

  /// Changes the noise from the next tick on and tells the sinks (a hand change: the run is no reference
  /// from then on). Call it between ticks, from the thread that steps; throws ParameterError for bad levels.
  void changeNoise(const SaaNoise& noise);
  const World& world() const { return world_; }
  /// A live change of the population rates (between ticks; World::setPopulationRates).
  void setPopulationRates(const PopulationConfig& rates) { world_.setPopulationRates(rates); }
  const RunDescription& description() const { return description_; }
  const SensorData& sensors() const { return sensors_; }

 private:
  /// Tick 0: the constants the controllers reported and the condition fix the identity; ok, or why the
  /// replies cannot make one run.
  StepOutcome fix(const std::optional<ConditionSample>& condition);
  /// Ok, or why this tick's commands cannot be stepped (a wheel speed that is NaN or infinite, a request
  /// code past kCacheDrop), naming the controller, its node, the robot and the tick.
  StepOutcome invalidCommand(uint64_t tick) const;
  void recordBeforeDecide(uint64_t tick);
  void recordAfterStep(uint64_t tick, const std::optional<ConditionSample>& condition, uint32_t delivered);
  /// The run without its condition, as words: what a resumed run must match.
  std::string checkpointWords() const;
  /// A digest of V and its target in every tick before `ticks` (equal: the world sees the same condition).
  uint64_t conditionDigest(uint64_t ticks);

  RunDescription description_;
  RunSchedule schedule_;
  World world_;
  ControllerPort& controllers_;
  EnvironmentPort& environment_;
  std::vector<RunSink*> sinks_;
  std::string label_;
  SensorData sensors_;
  std::pair<bool, std::size_t> cache_state_{false, 0};  // last recorded (exists, blocks)
  std::optional<ConditionSample> recorded_condition_;
  std::function<void(uint64_t)> after_step_;
  bool resumed_ = false;  // resume() replaced begin()
};

}  // namespace swarm_forage
