#pragma once
// Live knobs (dynamic_reconfigure) checked like start-up parameters: a change is applied whole or refused
// whole, and the config's `last_change` tells the client which, and why.
#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>

#include <boost/thread/recursive_mutex.hpp>
#include <functional>
#include <string>

#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

template <typename Config>
class Reconfigurable {
 public:
  /// `apply(requested)` applies a change and returns the config now in force, or throws ParameterError
  /// and changes nothing. It is called once here with `current`, the start-up parameters.
  Reconfigurable(const ros::NodeHandle& pnh, const Config& current,
                 std::function<Config(const Config&)> apply)
      : server_(mutex_, pnh), who_(pnh.getNamespace()), current_(current), apply_(std::move(apply)) {
    current_.last_change = "start-up parameters";
    server_.updateConfig(current_);
    server_.setCallback([this](Config& requested, uint32_t) { onChange(requested); });  // calls it once
    started_ = true;
  }

 private:
  void onChange(Config& requested) {
    try {
      Config applied = apply_(requested);
      applied.last_change = started_ ? "applied" : current_.last_change;
      current_ = applied;
    } catch (const ParameterError& e) {
      current_.last_change = std::string("refused: ") + e.what();
      ROS_ERROR("%s: change refused: %s", who_.c_str(), e.what());
    }
    requested = current_;  // what the server publishes and answers
  }

  // Ours, not the server's: updateConfig() then takes it like the callbacks do (no deadlock warning).
  boost::recursive_mutex mutex_;
  dynamic_reconfigure::Server<Config> server_;
  std::string who_;  // the node's (or nodelet's) name, for the log
  Config current_;
  std::function<Config(const Config&)> apply_;
  bool started_ = false;  // past the first call, which setCallback makes with the start-up parameters
};

}  // namespace swarm_forage
