#include "swarm_forage/core/run/simulation.hpp"

namespace swarm_forage {

namespace {
// As the node graph hands them to a controller node (float fields of world/sensors), so that a headless
// run is bit-identical to one through the graph.
Vec2 nestCentre(const ArenaConfig& a) {
  const Rect n = a.nest();
  return {static_cast<float>((n.min_x + n.max_x) / 2), static_cast<float>((n.min_y + n.max_y) / 2)};
}
LineOfSight wireSight(const LineOfSight& s) { return {static_cast<float>(s.cell), s.radius}; }
}  // namespace

Simulation::Simulation(const WorldConfig& world, const std::string& controller,
                       const ControllerConfigs& configs, unsigned threads)
    : pool_(std::make_shared<WorkerPool>(threads)),
      world_(configuredFor(world, controller)),
      batch_(makeController(controller,
                            sharingWorld(configs, nestCentre(world.arena), wireSight(world_.config().sight)),
                            world.seed, 0, world.n_robots, pool_)) {
  world_.setPool(pool_);
}

StepResult Simulation::step(double throttle) {
  sense();
  decide();
  return advance(throttle);
}

void Simulation::sense() { world_.sense(sensors_); }

void Simulation::decide() { batch_->step(world_.tick(), sensors_, commands_, status_); }

StepResult Simulation::advance(double throttle) { return world_.step(commands_, throttle, status_.tasks); }

}  // namespace swarm_forage
