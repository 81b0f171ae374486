#pragma once
// environment_node: publishes the environmental condition V(t) on environment/throttle for every tick
// the world's /clock announces.
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>

#include <functional>

#include "swarm_forage/core/waveform.hpp"

namespace swarm_forage {

class EnvironmentRos {
 public:
  EnvironmentRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish = {});

 private:
  void onClock(const rosgraph_msgs::Clock::ConstPtr& msg);

  ros::NodeHandle nh_, pnh_;
  ros::Subscriber clock_sub_;
  ros::Publisher throttle_pub_;
  WaveformConfig waveform_;
  uint64_t ns_per_tick_ = 0;
  double ticks_per_second_ = 5.0;
};

}  // namespace swarm_forage
