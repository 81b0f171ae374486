#pragma once
// The in-process ports of the run engine: one controller batch for the whole swarm and the condition
// computed where it is applied (run_experiment, probes, benchmarks). A run through them is bit-identical to
// one through the node graph.
#include <memory>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/run/run_ports.hpp"

namespace swarm_forage {

class InProcessControllers : public ControllerPort {
 public:
  /// The batches of every run share `pool` (its threads do not change the results).
  InProcessControllers(ControllerConfigs configs, std::shared_ptr<WorkerPool> pool);
  void begin(const RunDescription& run, const World& world) override;
  StepOutcome decide(uint64_t tick, const World& world, const SensorData& sensors) override;
  const CommandData& commands() const override { return commands_; }
  const std::vector<StatusRecord>& status() const override { return status_; }
  /// The batch's own status of the last tick.
  const ControllerStatus& batchStatus() const { return batch_status_; }
  std::string constants() const override { return constants_; }
  void persist(StateArchive& a) override;

 private:
  ControllerConfigs configs_;
  std::shared_ptr<WorkerPool> pool_;
  std::unique_ptr<ControllerBatch> batch_;
  RunDescription run_;
  std::string constants_;  // reported with tick 0's status, as a controller node does
  CommandData commands_;
  ControllerStatus batch_status_;
  std::vector<StatusRecord> status_;
};

/// The condition computed at each tick (a run of known length: the condition is checked against it).
class InProcessEnvironment : public EnvironmentPort {
 public:
  InProcessEnvironment(const Condition& condition, double ticks_per_second)
      : condition_(condition), ticks_per_second_(ticks_per_second) {}
  std::optional<ConditionSample> condition(uint64_t tick) override {
    return conditionAt(condition_, tick, ticks_per_second_);
  }

 private:
  Condition condition_;
  double ticks_per_second_;
};

}  // namespace swarm_forage
