#include "swarm_forage/core/run/simulation.hpp"

namespace swarm_forage {

Simulation::Simulation(const WorldConfig& world, const std::string& controller,
                       const ControllerConfigs& configs, unsigned threads)
    : Simulation(world, controller, configs, std::make_shared<WorkerPool>(threads)) {}

Simulation::Simulation(const WorldConfig& world, const std::string& controller,
                       const ControllerConfigs& configs, std::shared_ptr<WorkerPool> pool)
    : pool_(std::move(pool)), world_(configuredFor(world, controller)), controllers_(configs, pool_) {
  world_.setPool(pool_);
  RunDescription run;
  run.controller = controller;
  run.world = world_.config();
  controllers_.begin(run, world_);
}

StepResult Simulation::step(Throttling throttle) {
  world_.sense(sensors_);
  controllers_.decide(world_.tick(), world_, sensors_);
  return world_.step(controllers_.commands(), throttle, controllers_.batchStatus().tasks);
}

}  // namespace swarm_forage
