#include "swarm_forage/core/simulation.hpp"

namespace swarm_forage {

namespace {
Vec2 nestCentre(const ArenaConfig& a) {
  const Rect n = a.nest();
  return {(n.min_x + n.max_x) / 2, (n.min_y + n.max_y) / 2};
}
}  // namespace

Simulation::Simulation(const WorldConfig& world, const std::string& controller,
                       const ControllerConfigs& configs)
    : world_(configuredFor(world, controller)),
      batch_(makeController(controller, sharingWorld(configs, nestCentre(world.arena), world_.config().sight),
                            world.seed, 0, world.n_robots)) {}

StepResult Simulation::step(double throttle) {
  world_.sense(sensors_);
  batch_->step(world_.tick(), sensors_, commands_, status_);
  return world_.step(commands_, throttle, status_.tasks);
}

}  // namespace swarm_forage
