#include "swarm_forage/ros/convert.hpp"

#include <algorithm>

namespace swarm_forage {

void toMsg(const SensorData& s, SensorBatch& m) {
  m.x = s.x;
  m.y = s.y;
  m.theta = s.theta;
  m.threatened = s.threatened;
  m.obstacle_x = s.obstacle_x;
  m.obstacle_y = s.obstacle_y;
  m.light_x = s.light_x;
  m.light_y = s.light_y;
  m.ground = s.ground;
  m.events = s.events;
  m.carried_block = s.carried_block;
}

void fromMsg(const SensorBatch& m, SensorData& s) {
  s.x = m.x;
  s.y = m.y;
  s.theta = m.theta;
  s.threatened = m.threatened;
  s.obstacle_x = m.obstacle_x;
  s.obstacle_y = m.obstacle_y;
  s.light_x = m.light_x;
  s.light_y = m.light_y;
  s.ground = m.ground;
  s.events = m.events;
  s.carried_block = m.carried_block;
}

void toMsg(const CommandData& c, CommandBatch& m) {
  m.first_id = c.first_id;
  m.left = c.left;
  m.right = c.right;
  m.request = c.request;
}

void mergeInto(const CommandBatch& m, CommandData& all) {
  std::copy(m.left.begin(), m.left.end(), all.left.begin() + m.first_id);
  std::copy(m.right.begin(), m.right.end(), all.right.begin() + m.first_id);
  std::copy(m.request.begin(), m.request.end(), all.request.begin() + m.first_id);
}

void toMsg(const ControllerStatus& s, SwarmStatus& m) {
  m.in_avoidance = s.in_avoidance;
  m.state_names = s.state_names;
  m.state_counts = s.state_counts;
  m.generalists = s.generalists;
  m.harvesters = s.harvesters;
  m.collectors = s.collectors;
}

}  // namespace swarm_forage
