#pragma once
// tf for world_node: static map -> arena, nest and (once one exists) cache, and map -> robot_<id> each tick
// for a bounded subset of robots (~tf_robots), never for the whole swarm.
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <memory>
#include <optional>
#include <vector>

#include "swarm_forage/core/world/sensing.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

class WorldFrames {
 public:
  static constexpr int kMaxRobots = 64;
  /// Reads ~tf_robots: a count (the first N robots, 0 = none) or a list of ids, at most kMaxRobots;
  /// throws ParameterError otherwise.
  explicit WorldFrames(const ros::NodeHandle& pnh);
  /// The static frames of a new run (the arena and nest; the cache, if any).
  void beginRun(const World& world);
  /// This tick's robot frames, stamped `stamp`; the cache's frame when it moved or appeared.
  void publish(const World& world, const SensorData& sensors, const ros::Time& stamp);

 private:
  std::optional<int> count_;  // the first N robots ...
  std::vector<int> ids_;      // ... or these
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> static_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> dynamic_;
  std::vector<uint32_t> robot_ids_;                      // this run's framed robots ...
  std::vector<geometry_msgs::TransformStamped> robots_;  // ... and their transforms
  bool cache_sent_ = false;
  double cache_x_ = 0, cache_y_ = 0;
};

}  // namespace swarm_forage
