#include "swarm_forage/ros/nodes/health.hpp"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

unsigned char HealthThresholds::level(double value) const {
  using S = diagnostic_msgs::DiagnosticStatus;
  return value >= error ? S::ERROR : value >= warn ? S::WARN : S::OK;
}

HealthThresholds readHealthThresholds(const ros::NodeHandle& pnh, const std::string& name, double warn,
                                      double error, double max) {
  HealthThresholds t;
  const std::string key = "diag_" + name;
  t.warn = paramInRange(pnh, key + "_warn", warn, 0.0, max);
  t.error = paramInRange(pnh, key + "_error", error, t.warn, max);  // the range names ~<key>_warn's value
  return t;
}

HealthReporter::HealthReporter(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& task,
                               Fill fill, bool timer)
    // The private namespace names a nodelet too (this_node::getName() would be its manager's).
    : updater_(nh, pnh, pnh.getNamespace()),
      period_(paramInRange(pnh, "diagnostic_period", 1.0, 0.05, 60.0)) {
  updater_.setHardwareID("none");  // a simulated node has no device
  updater_.add(task, std::move(fill));
  if (timer) {
    ros::NodeHandle queue(pnh);
    timer_ = queue.createWallTimer(period_, [this](const ros::WallTimerEvent&) { report(); });
  }
}

void HealthReporter::poll() {
  if (ros::WallTime::now() - last_ >= period_) report();
}

void HealthReporter::report() {
  last_ = ros::WallTime::now();
  updater_.force_update();
}

}  // namespace swarm_forage
