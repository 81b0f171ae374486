#pragma once
// A node's health on /diagnostics (diagnostic_updater), reported on a wall-time schedule: simulated time
// stops when a run stalls, which is exactly when the report matters.
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include <functional>
#include <string>

namespace swarm_forage {

/// A WARN and an ERROR threshold read from ~diag_<name>_warn and ~diag_<name>_error, error >= warn.
struct HealthThresholds {
  double warn = 0, error = 0;
  /// OK, WARN or ERROR for `value` (higher is worse).
  unsigned char level(double value) const;
};
/// Defaults and ranges: the rows diag_<name>_warn and diag_<name>_error of the parameter table.
HealthThresholds readHealthThresholds(const ros::NodeHandle& pnh, const std::string& name);

/// True at most once per `period` wall seconds: a log throttle that also works while simulated time stands
/// still (ROS_*_THROTTLE follows /clock, and never fires before the first one).
class WallThrottle {
 public:
  explicit WallThrottle(double period) : period_(period) {}
  bool due() {
    const ros::WallTime now = ros::WallTime::now();
    if (!last_.isZero() && (now - last_).toSec() < period_) return false;
    last_ = now;
    return true;
  }

 private:
  double period_;
  ros::WallTime last_;
};

class HealthReporter {
 public:
  using Fill = std::function<void(diagnostic_updater::DiagnosticStatusWrapper&)>;
  /// One status named `task` (shown as "<node>: <task>"), filled by `fill` every ~diagnostic_period wall
  /// seconds (default 1). With `timer`, a wall timer on pnh's queue reports; without, call poll().
  HealthReporter(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& task, Fill fill,
                 bool timer);
  /// Reports when a period has passed since the last report (cheap otherwise).
  void poll();
  /// Reports now (the end of a run, before the node may exit).
  void report();

 private:
  diagnostic_updater::Updater updater_;
  ros::WallDuration period_;
  ros::WallTime last_;
  ros::WallTimer timer_;
};

}  // namespace swarm_forage
