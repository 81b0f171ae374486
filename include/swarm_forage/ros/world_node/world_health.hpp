#pragma once
// world_node's status on /diagnostics: its pace, how long each peer took to answer, who it is waiting for,
// how runs ended and the bag's state. Fed by the stepping thread, reported from it on a wall-time schedule.
#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "swarm_forage/ros/nodes/health.hpp"

namespace swarm_forage {

class WorldHealth {
 public:
  using Values = std::function<void(diagnostic_updater::DiagnosticStatusWrapper&)>;
  /// `missing()`: this tick's replies still missing and from whom; `more` adds the node's other values.
  /// Reads ~diag_wait_warn and ~diag_wait_error [s]: how long a tick may wait for its replies (lockstep) or
  /// a controller stay silent (realtime) before the status turns WARN, then ERROR.
  WorldHealth(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, bool lockstep,
              std::function<std::string()> missing, Values more);

  /// What the node is doing between ticks: waiting for its peers, a run finished or stopped (ERROR).
  void phase(const std::string& what, unsigned char level);
  void beginRun(uint32_t run, uint64_t ticks, uint32_t robots);
  void tickStarted(uint64_t tick);
  /// `node` answered the current tick (lockstep) or sent its latest commands (realtime).
  void replied(const std::string& node);
  /// The current tick has every reply (lockstep).
  void repliesIn();
  void stepped() { ++ticks_done_; }
  void stepTimedOut() { ++step_timeouts_; }
  void poll() { reporter_.poll(); }
  void reportNow() { reporter_.report(); }
  /// OK, WARN or ERROR for having waited `seconds` (~diag_wait_warn, ~diag_wait_error).
  unsigned char waitLevel(double seconds) const { return wait_.level(seconds); }

 private:
  void fill(diagnostic_updater::DiagnosticStatusWrapper& s);
  /// Seconds the current tick has waited (lockstep) or the quietest peer has been silent (realtime).
  double waiting(const ros::WallTime& now) const;

  bool lockstep_;
  std::function<std::string()> missing_;
  Values more_;
  HealthThresholds wait_;
  uint32_t run_ = 0, robots_ = 0;
  uint64_t ticks_ = 0, tick_ = 0, ticks_done_ = 0, step_timeouts_ = 0;
  bool running_ = false, waiting_ = false;
  ros::WallTime tick_started_;
  std::map<std::string, double> waits_, current_waits_;  // lockstep: each peer's answer time [s]
  std::map<std::string, ros::WallTime> heard_;           // when each peer answered last
  uint64_t reported_ticks_ = 0;
  ros::WallTime reported_at_;
  std::string phase_ = "starting";
  unsigned char phase_level_ = 0;
  HealthReporter reporter_;  // last: it may report as soon as it exists
};

}  // namespace swarm_forage
