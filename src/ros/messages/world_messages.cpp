#include "swarm_forage/ros/messages/world_messages.hpp"

#include <boost/make_shared.hpp>

#include "swarm_forage/ros/messages/batch_messages.hpp"

namespace swarm_forage {

Nest nestMsg(const ArenaConfig& a) {
  Nest n;
  const Rect r = a.nest();
  n.center_x = static_cast<float>((r.min_x + r.max_x) / 2);
  n.center_y = static_cast<float>((r.min_y + r.max_y) / 2);
  n.size_x = static_cast<float>(r.width());
  n.size_y = static_cast<float>(r.height());
  for (int l = 0; l < ArenaConfig::kLights; ++l) {
    n.light_x.push_back(static_cast<float>(a.light(l).x()));
    n.light_y.push_back(static_cast<float>(a.light(l).y()));
  }
  return n;
}

CacheArray cacheMsg(const StaticCache& cache) {
  CacheArray m;
  if (!cache.exists()) return m;
  m.id = {0};
  m.x = {static_cast<float>(cache.center().x())};
  m.y = {static_cast<float>(cache.center().y())};
  m.size = {static_cast<float>(cache.area().width())};
  m.blocks = {static_cast<uint32_t>(cache.size())};
  return m;
}

CacheArray cachesMsg(const StaticCache& cache, uint64_t tick, const ros::Time& stamp) {
  CacheArray msg = cacheMsg(cache);
  msg.header.stamp = stamp;
  msg.header.frame_id = "map";
  msg.tick = tick;
  return msg;
}

SensorBatch::Ptr sensorsMsg(const World& world, const SensorData& sensors, uint64_t tick, uint32_t run,
                            const std::string& controller, const ros::Time& stamp) {
  const WorldConfig& c = world.config();
  auto msg = boost::make_shared<SensorBatch>();
  msg->header.stamp = stamp;
  msg->tick = tick;
  msg->run = run;
  msg->seed = c.seed;
  msg->controller = controller;
  msg->swarm_size = c.n_robots;
  const Rect nest = c.arena.nest();
  msg->nest_x = static_cast<float>((nest.min_x + nest.max_x) / 2);
  msg->nest_y = static_cast<float>((nest.min_y + nest.max_y) / 2);
  msg->los_cell = static_cast<float>(c.sight.cell);
  msg->los_radius = static_cast<uint32_t>(c.sight.radius);
  toMsg(sensors, *msg);
  return msg;
}

geometry_msgs::TransformStamped staticFrame(const std::string& child, double x, double y) {
  geometry_msgs::TransformStamped t;
  t.header.frame_id = "map";
  t.child_frame_id = child;
  t.transform.translation.x = x;
  t.transform.translation.y = y;
  t.transform.rotation.w = 1.0;
  return t;
}
RobotStateArray robotsMsg(const SensorData& sensors, uint64_t tick, const ros::Time& stamp) {
  RobotStateArray robots;
  robots.header.stamp = stamp;
  robots.header.frame_id = "map";
  robots.tick = tick;
  robots.x = sensors.x;
  robots.y = sensors.y;
  robots.theta = sensors.theta;
  robots.carried_block = sensors.carried_block;
  robots.threatened = sensors.threatened;
  return robots;
}

BlockArray blocksMsg(const BlockField& field, const SensorData& sensors, uint64_t tick,
                     const ros::Time& stamp) {
  BlockArray blocks;
  blocks.header.stamp = stamp;
  blocks.header.frame_id = "map";
  blocks.tick = tick;
  for (std::size_t b = 0; b < field.size(); ++b) {
    const auto id = static_cast<int32_t>(b);
    const int32_t carrier = field.carrier(id);
    blocks.id.push_back(static_cast<uint32_t>(b));
    blocks.x.push_back(carrier >= 0 ? sensors.x[carrier] : static_cast<float>(field.x(id)));
    blocks.y.push_back(carrier >= 0 ? sensors.y[carrier] : static_cast<float>(field.y(id)));
    blocks.kind.push_back(field.kind(id));
    blocks.size_x.push_back(static_cast<float>(field.sizeX(id)));
    blocks.size_y.push_back(static_cast<float>(field.sizeY(id)));
    blocks.carrier.push_back(carrier);
  }
  return blocks;
}

}  // namespace swarm_forage
