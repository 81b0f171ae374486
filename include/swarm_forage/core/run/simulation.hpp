#pragma once
// A run in process stepped by hand, without records or an end: the world and the in-process controller
// port, for probes, benchmarks and tests that move robots or look between ticks. A recorded run is a Run
// (run.hpp) with the same port.
#include <memory>
#include <string>

#include "swarm_forage/core/run/in_process.hpp"

namespace swarm_forage {

class Simulation {
 public:
  /// The world gets the features `controller` needs (line of sight, cache). Throws ParameterError for
  /// invalid configurations. `threads` (0: one per core) run the world and the controllers; results do
  /// not depend on it.
  Simulation(const WorldConfig& world, const std::string& controller, const ControllerConfigs& configs = {},
             unsigned threads = 1);
  /// The same on a pool of the caller's.
  Simulation(const WorldConfig& world, const std::string& controller, const ControllerConfigs& configs,
             std::shared_ptr<WorkerPool> pool);
  /// One tick: sense, the controllers' decision, the world's step under `throttle`.
  StepResult step(Throttling throttle = {});

  World& world() { return world_; }
  const SensorData& sensors() const { return sensors_; }  // the last tick's readings
  const CommandData& commands() const { return controllers_.commands(); }
  const ControllerStatus& status() const { return controllers_.batchStatus(); }

 private:
  std::shared_ptr<WorkerPool> pool_;
  World world_;
  InProcessControllers controllers_;
  SensorData sensors_;
};

}  // namespace swarm_forage
