#include "swarm_forage/ros/messages/batch_messages.hpp"

#include <algorithm>

namespace swarm_forage {

namespace {
// SensorData and SensorBatch name their arrays alike: one list of fields serves both directions.
template <typename From, typename To>
void copySensorArrays(const From& f, To& t) {
  t.x = f.x;
  t.y = f.y;
  t.theta = f.theta;
  t.threatened = f.threatened;
  t.obstacle_x = f.obstacle_x;
  t.obstacle_y = f.obstacle_y;
  t.light_x = f.light_x;
  t.light_y = f.light_y;
  t.ground = f.ground;
  t.events = f.events;
  t.carried_block = f.carried_block;
  t.active = f.active;
  t.los_block_offset = f.los_block_offset;
  t.los_block_id = f.los_block_id;
  t.los_block_x = f.los_block_x;
  t.los_block_y = f.los_block_y;
  t.los_cache_offset = f.los_cache_offset;
  t.los_cache_id = f.los_cache_id;
  t.los_cache_x = f.los_cache_x;
  t.los_cache_y = f.los_cache_y;
  t.los_cache_blocks = f.los_cache_blocks;
}
// The message holds the status's task counts flat: one list of field pairs, (status, message), serves both
// directions.
template <typename Status, typename Msg, typename Copy>
void statusFields(Status& s, Msg& m, Copy copy) {
  copy(s.in_avoidance, m.in_avoidance);
  copy(s.stalled, m.stalled);
  copy(s.state_names, m.state_names);
  copy(s.state_counts, m.state_counts);
  copy(s.tasks.generalists, m.generalists);
  copy(s.tasks.harvesters, m.harvesters);
  copy(s.tasks.collectors, m.collectors);
}
}  // namespace

void toMsg(const SensorData& s, SensorBatch& m) { copySensorArrays(s, m); }
void fromMsg(const SensorBatch& m, SensorData& s) { copySensorArrays(m, s); }

void toMsg(const CommandData& c, CommandBatch& m) {
  m.first_id = c.first_id;
  m.left = c.left;
  m.right = c.right;
  m.request = c.request;
  m.task = c.task;
}

void mergeInto(const CommandBatch& m, CommandData& all) {
  std::copy(m.left.begin(), m.left.end(), all.left.begin() + m.first_id);
  std::copy(m.right.begin(), m.right.end(), all.right.begin() + m.first_id);
  std::copy(m.request.begin(), m.request.end(), all.request.begin() + m.first_id);
  std::copy(m.task.begin(), m.task.end(), all.task.begin() + m.first_id);
}

void toMsg(const ControllerStatus& s, SwarmStatus& m) {
  statusFields(s, m, [](const auto& from, auto& to) { to = from; });
}

void fromMsg(const SwarmStatus& m, ControllerStatus& s) {
  statusFields(s, m, [](auto& to, const auto& from) { to = from; });
}

}  // namespace swarm_forage
