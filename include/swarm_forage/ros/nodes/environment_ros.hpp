#pragma once
// environment_node: publishes the environmental condition V(t) on environment/throttle for every tick
// the world's /clock announces. Its condition can be changed while it runs (dynamic_reconfigure).
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <swarm_forage/EnvironmentConfig.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/ros/params/reconfigure.hpp"

namespace swarm_forage {

class EnvironmentRos {
 public:
  EnvironmentRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish = {});
  /// Its private parameters (known_params.cpp): any other is refused at start-up.
  static std::vector<std::string> parameterNames();

 private:
  void onClock(const rosgraph_msgs::Clock::ConstPtr& msg);
  /// Applies a requested condition, checked like the start-up parameters (throws ParameterError).
  EnvironmentConfig reconfigure(const EnvironmentConfig& requested);

  ros::NodeHandle nh_, pnh_;
  ros::Subscriber clock_sub_;
  ros::Publisher throttle_pub_;
  Condition condition_;
  uint64_t ns_per_tick_ = 0;
  double ticks_per_second_ = 5.0;
  int ticks_ = 0;
  std::unique_ptr<Reconfigurable<EnvironmentConfig>> reconfigure_;  // last: its first call uses the rest
};

}  // namespace swarm_forage
