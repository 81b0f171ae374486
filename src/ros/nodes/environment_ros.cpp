#include "swarm_forage/ros/nodes/environment_ros.hpp"

#include <swarm_forage/Throttle.h>

#include <cmath>
#include <cstdio>

#include "swarm_forage/ros/messages/condition_ros.hpp"
#include "swarm_forage/ros/messages/run_messages.hpp"
#include "swarm_forage/ros/params/known_params.hpp"
#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

namespace {
// cfg/Environment.cfg names its knobs as the condition's fields.
EnvironmentConfig toConfig(const Condition& c) {
  EnvironmentConfig e;
  return assignCondition(e, c, &EnvironmentConfig::beta);
}
}  // namespace

EnvironmentRos::EnvironmentRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                               std::function<void(int)>)
    : nh_(nh), pnh_(pnh) {
  refuseUnknownParams(pnh_, parameterNames(), "environment_node");
  const double tps = ticks_per_second_ = readParam<double>(pnh_, "ticks_per_second");
  ticks_ = readParam<int>(pnh_, "ticks");
  condition_ = readCondition(NodeParams(pnh_), static_cast<uint64_t>(ticks_), tps);
  ns_per_tick_ = static_cast<uint64_t>(std::llround(1e9 / tps));
  throttle_pub_ = nh_.advertise<Throttle>("environment/throttle", 64);
  clock_sub_ =
      nh_.subscribe("/clock", 64, &EnvironmentRos::onClock, this, ros::TransportHints().tcpNoDelay());
  reconfigure_ = std::make_unique<Reconfigurable<EnvironmentConfig>>(
      pnh_, toConfig(condition_), [this](const EnvironmentConfig& c) { return reconfigure(c); });
}

EnvironmentConfig EnvironmentRos::reconfigure(const EnvironmentConfig& requested) {
  // The start-up rule; throws: nothing changes.
  condition_ = conditionForRun(conditionFrom(requested, &EnvironmentConfig::beta),
                               static_cast<uint64_t>(ticks_), ticks_per_second_);
  ROS_INFO("environment: %s", condition_.label().c_str());
  return toConfig(condition_);
}

void EnvironmentRos::onClock(const rosgraph_msgs::Clock::ConstPtr& msg) {
  const uint64_t tick = (msg->clock.toNSec() + ns_per_tick_ / 2) / ns_per_tick_;
  Throttle t = throttleMsg(condition_, tick, ticks_per_second_, ns_per_tick_);
  t.header.stamp = msg->clock;
  throttle_pub_.publish(t);
}

}  // namespace swarm_forage
