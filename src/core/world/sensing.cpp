#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

void SensorData::resize(std::size_t n) {
  for (auto* v : {&x, &y, &theta, &obstacle_x, &obstacle_y, &light_x, &light_y}) v->assign(n, 0.f);
  for (auto* v : {&threatened, &ground, &events}) v->assign(n, 0);
  carried_block.assign(n, -1);
  active.clear();
  clearLineOfSight();
}

void SensorData::clearLineOfSight() {
  for (auto* v : {&los_block_offset, &los_cache_offset, &los_cache_blocks}) v->clear();
  for (auto* v : {&los_block_id, &los_cache_id}) v->clear();
  for (auto* v : {&los_block_x, &los_block_y, &los_cache_x, &los_cache_y}) v->clear();
}

void CommandData::resize(std::size_t n) {
  left.assign(n, 0.f);
  right.assign(n, 0.f);
  request.assign(n, kNone);
  task.assign(n, kTaskNone);
}

}  // namespace swarm_forage
