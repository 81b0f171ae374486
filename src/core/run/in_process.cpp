#include "swarm_forage/core/run/in_process.hpp"

#include "swarm_forage/core/controllers/controller_constants.hpp"

namespace swarm_forage {

namespace {
// As the node graph hands them to a controller node (float fields of world/sensors), so that a run in
// process is bit-identical to one through the graph.
Vec2 nestCentre(const ArenaConfig& a) {
  const Rect n = a.nest();
  return {static_cast<float>((n.min_x + n.max_x) / 2), static_cast<float>((n.min_y + n.max_y) / 2)};
}
LineOfSight wireSight(const LineOfSight& s) { return {static_cast<float>(s.cell), s.radius}; }
}  // namespace

InProcessControllers::InProcessControllers(ControllerConfigs configs, std::shared_ptr<WorkerPool> pool)
    : configs_(std::move(configs)), pool_(std::move(pool)) {}

void InProcessControllers::begin(const RunDescription& run, const World& world) {
  const WorldConfig& c = world.config();
  batch_ = makeController(run.controller, sharingWorld(configs_, nestCentre(c.arena), wireSight(c.sight)),
                          c.seed, 0, c.n_robots, pool_);
  run_ = run;
  constants_ = describeConstants(run.controller, configs_);
  status_.assign(1, StatusRecord{});
}

void InProcessControllers::persist(StateArchive& a) {
  a.section("controllers");
  batch_->persist(a);
}

StepOutcome InProcessControllers::decide(uint64_t tick, const World& world, const SensorData& sensors) {
  batch_->step(tick, world.perceived(sensors), commands_, batch_status_);
  status_[0] = statusRecord(batch_status_, commands_, tick, run_.run, run_.world.n_robots, run_.controller,
                            tick == 0 ? constants_ : std::string());
  return StepOutcome::ok();
}

}  // namespace swarm_forage
