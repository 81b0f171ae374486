#pragma once
// metrics_node: turns per-tick performance and interference into per-interval P, p and n_ca
// (DESIGN section 5) on metrics/performance, identically from a live run and from `rosbag play`.
#include <ros/ros.h>
#include <swarm_forage/Performance.h>
#include <swarm_forage/SwarmStatus.h>

#include <fstream>
#include <functional>
#include <map>
#include <optional>

#include "swarm_forage/core/interval_metrics.hpp"
#include "swarm_forage/ros/tick_gate.hpp"

namespace swarm_forage {

class MetricsRos {
 public:
  /// `finish(0)` is called after the final sample of a run when ~exit_on_final is true.
  MetricsRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish = {});

 private:
  struct Pending {
    std::optional<Performance> performance;
    RangeCoverage status{"swarm/status"};
    uint32_t in_avoidance = 0;
  };
  void onPerformance(const Performance::ConstPtr& msg);
  void onStatus(const ros::MessageEvent<const SwarmStatus>& event);
  /// Follows a newer run; false for a message of an older one.
  bool follow(uint32_t run);
  Pending& pending(uint64_t tick, uint32_t swarm_size);
  void drain();
  void publish(const IntervalSample& s, const ros::Time& stamp);

  ros::NodeHandle nh_, pnh_;
  ros::Subscriber performance_sub_, status_sub_;
  ros::Publisher interval_pub_;
  std::function<void(int)> finish_;
  uint32_t interval_ = 1000;
  bool exit_on_final_ = false;
  std::ofstream csv_;

  bool following_ = false;
  uint32_t run_ = 0, swarm_size_ = 0;
  std::optional<uint64_t> next_tick_;
  std::map<uint64_t, Pending> pending_;
  IntervalAccumulator accumulator_{1000};
  uint64_t ticks_seen_ = 0, in_avoidance_total_ = 0;
};

}  // namespace swarm_forage
