// The world's persistent state for checkpoints (docs/runs-and-bags.md): what one tick hands to the next.
// Per-tick scratch (grid, slots, bands, readings, pushes) is rebuilt by the next tick and not saved.
#include "swarm_forage/core/util/state_archive.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

// The structs the world archives, field by field (StateArchive::io).
void persistValue(StateArchive& a, Rect& r) { a.io(r.min_x, r.min_y, r.max_x, r.max_y); }
void persistValue(StateArchive& a, DeviceNoise& d) { a.io(d.model, d.level); }
void persistValue(StateArchive& a, SaaNoise& n) {
  a.io(n.proximity, n.light, n.position, n.heading, n.wheels, n.ground);
}
void persistValue(StateArchive& a, PopulationConfig& c) {
  a.io(c.death, c.birth, c.malfunction, c.repair, c.max_size);
}
void persistValue(StateArchive& a, BlockPenaltyHandler::Penalty& p) {
  a.io(p.robot, p.id, p.penalty, p.start);
}

void World::persist(StateArchive& a) {
  a.section("world");
  a.io(tick_, cumulative_);
  a.io(config_.noise);  // a hand change (Run::changeNoise) outlives the start-up value
  for (auto* v : {&robots_.x, &robots_.y, &robots_.theta}) a.io(*v);
  a.io(robots_.carried, robots_.events, robots_.last_request, robots_.request_since);
  blocks_.persist(a);
  cache_.persist(a);
  population_.persist(a);
  pickup_penalties_.persist(a);
  drop_penalties_.persist(a);
  a.io(shadowed_lights_, shadow_masks_);
  if (!a.loading()) return;
  const std::size_t n = config_.n_robots;
  for (std::size_t size : {robots_.x.size(), robots_.y.size(), robots_.theta.size(), robots_.carried.size(),
                           robots_.events.size(), robots_.last_request.size(), robots_.request_since.size()})
    if (size != n)
      throw CheckpointError("the world holds " + std::to_string(size) + " robots, not " + std::to_string(n));
  grid_valid_ = false;
  clearance_valid_ = false;
}

void BlockField::persist(StateArchive& a) {
  a.section("blocks");
  a.io(seed_, draws_, version_, x_, y_, kind_, carrier_);
  a.io(cells_);  // kept as it grew: the order of blocks in a cell is what look-ups see first
  a.io(occupied_);
  if (a.loading() &&
      (cells_.size() != static_cast<std::size_t>(nx_) * ny_ || occupied_.size() != cells_.size()))
    throw CheckpointError("the block grid does not fit the arena");
  if (a.loading()) layOutNear();
}

void StaticCache::persist(StateArchive& a) {
  a.section("cache");
  a.io(capacity_, area_, exists_, blocks_);
}

void PoissonClock::persist(StateArchive& a) { a.io(rate_, last_, next_, scheduled_); }

void PopulationDynamics::persist(StateArchive& a) {
  a.section("population");
  a.io(config_);  // the rates in force: a live change (setRates) outlives the start-up ones
  a.io(changed_);
  for (PoissonClock* c : {&death_, &birth_, &malfunction_, &repair_}) c->persist(a);
  a.io(presence_, active_, queue_, events_.deaths, events_.births, events_.malfunctions, events_.repairs,
       events_.active, events_.present, events_.queue);
}

void BlockPenaltyHandler::persist(StateArchive& a) { a.io(list_, serving_); }

}  // namespace swarm_forage
