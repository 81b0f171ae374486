#include "swarm_forage/ros/nodes/health.hpp"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

unsigned char HealthThresholds::level(double value) const {
  using S = diagnostic_msgs::DiagnosticStatus;
  return value >= error ? S::ERROR : value >= warn ? S::WARN : S::OK;
}

HealthThresholds readHealthThresholds(const ros::NodeHandle& pnh, const std::string& name) {
  HealthThresholds t;
  const std::string key = "diag_" + name;
  t.warn = readParam<double>(pnh, key + "_warn");
  const ParamSpec& error = paramSpec(key + "_error");
  // The range names ~<key>_warn's value.
  t.error = paramInRange(pnh, key + "_error", fallbackOf<double>(error), t.warn, error.hi);
  return t;
}

HealthReporter::HealthReporter(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& task,
                               Fill fill, bool timer)
    // The private namespace names a nodelet too (this_node::getName() would be its manager's).
    : updater_(nh, pnh, pnh.getNamespace()), period_(readParam<double>(pnh, "diagnostic_period")) {
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
