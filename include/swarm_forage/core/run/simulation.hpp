#pragma once
// The core classes wired in one process, in lockstep, without ROS: the world and one controller batch
// for every robot. What a tick of the node graph does, for probes, benchmarks and headless runs.
#include <memory>
#include <string>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

class Simulation {
 public:
  /// The world gets the features `controller` needs (line of sight, cache); the controllers share its
  /// nest and line-of-sight geometry. Throws ParameterError for invalid configurations. `threads` (0: one
  /// per core) run the world and the controllers; results do not depend on it.
  Simulation(const WorldConfig& world, const std::string& controller, const ControllerConfigs& configs = {},
             unsigned threads = 1);
  /// One tick: sense, the controllers' step, the world's step under `throttle`.
  StepResult step(double throttle = 0.0);
  /// The three parts of step(), for callers that record between them (run_experiment).
  void sense();                         // this tick's readings
  void decide();                        // the controllers' commands and status from them
  StepResult advance(double throttle);  // the world's step

  World& world() { return world_; }
  const ControllerBatch& controller() const { return *batch_; }
  const SensorData& sensors() const { return sensors_; }  // this tick's readings (before step)
  const CommandData& commands() const { return commands_; }
  const ControllerStatus& status() const { return status_; }

 private:
  std::shared_ptr<WorkerPool> pool_;
  World world_;
  std::unique_ptr<ControllerBatch> batch_;
  SensorData sensors_;
  CommandData commands_;
  ControllerStatus status_;
};

}  // namespace swarm_forage
