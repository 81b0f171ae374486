#include "swarm_forage/ros/world_node/world_frames.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "swarm_forage/core/world/config.hpp"
#include "swarm_forage/ros/messages/world_messages.hpp"

namespace swarm_forage {

WorldFrames::WorldFrames(const ros::NodeHandle& pnh) {
  const std::string range = "~tf_robots must be a count in [0, " + std::to_string(kMaxRobots) +
                            "] or a list of at most " + std::to_string(kMaxRobots) + " robot ids (>= 0)";
  XmlRpc::XmlRpcValue v;
  if (!pnh.getParam("tf_robots", v)) {
    count_ = 0;
  } else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) {
    const int n = static_cast<int>(v);
    if (n < 0 || n > kMaxRobots) throw ParameterError(range + " (got " + std::to_string(n) + ")");
    count_ = n;
  } else if (v.getType() == XmlRpc::XmlRpcValue::TypeArray) {
    if (v.size() > kMaxRobots) throw ParameterError(range + " (got " + std::to_string(v.size()) + " ids)");
    for (int k = 0; k < v.size(); ++k) {
      if (v[k].getType() != XmlRpc::XmlRpcValue::TypeInt || static_cast<int>(v[k]) < 0)
        throw ParameterError(range + " (entry " + std::to_string(k) + " is not an id)");
      ids_.push_back(static_cast<int>(v[k]));
    }
  } else {
    throw ParameterError(range);
  }
  dynamic_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  static_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
}

void WorldFrames::beginRun(const World& world) {
  const Rect n = world.config().arena.nest();
  static_->sendTransform(
      {staticFrame("arena", 0, 0), staticFrame("nest", (n.min_x + n.max_x) / 2, (n.min_y + n.max_y) / 2)});
  cache_sent_ = false;
  robot_ids_.clear();
  const auto n_robots = static_cast<int>(world.config().n_robots);
  if (count_) {
    for (int i = 0; i < std::min(*count_, n_robots); ++i) robot_ids_.push_back(static_cast<uint32_t>(i));
  } else {
    for (int i : ids_) {
      if (i < n_robots)
        robot_ids_.push_back(static_cast<uint32_t>(i));
      else
        ROS_WARN("world: ~tf_robots lists robot %d, beyond this run's %d robots: no frame for it", i,
                 n_robots);
    }
  }
  robots_.clear();
  for (uint32_t i : robot_ids_) robots_.push_back(staticFrame("robot_" + std::to_string(i), 0, 0));
}

void WorldFrames::publish(const World& world, const SensorData& s, const ros::Time& stamp) {
  for (std::size_t k = 0; k < robots_.size(); ++k) {
    geometry_msgs::TransformStamped& t = robots_[k];
    const uint32_t i = robot_ids_[k];
    t.header.stamp = stamp;
    t.transform.translation.x = s.x[i];
    t.transform.translation.y = s.y[i];
    t.transform.rotation.z = std::sin(0.5 * s.theta[i]);
    t.transform.rotation.w = std::cos(0.5 * s.theta[i]);
  }
  if (!robots_.empty()) dynamic_->sendTransform(robots_);
  const StaticCache& cache = world.cache();
  if (cache.exists() && (!cache_sent_ || cache.center().x() != cache_x_ || cache.center().y() != cache_y_)) {
    cache_x_ = cache.center().x();
    cache_y_ = cache.center().y();
    static_->sendTransform(staticFrame("cache", cache_x_, cache_y_));
    cache_sent_ = true;
  }
}

}  // namespace swarm_forage
