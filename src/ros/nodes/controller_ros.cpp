#include "swarm_forage/ros/nodes/controller_ros.hpp"

#include <std_msgs/String.h>

#include <algorithm>
#include <utility>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/ros/messages/batch_messages.hpp"
#include "swarm_forage/ros/messages/run_messages.hpp"
#include "swarm_forage/ros/params/known_params.hpp"
#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

ControllerRos::ControllerRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)>)
    : nh_(nh), pnh_(pnh) {
  controller_ = paramController(NodeParams(pnh_));  // first: a plugin's constants are parameters once loaded
  putControllerDefaults(pnh_, controller_);
  refuseUnknownParams(pnh_, parameterNames(), "controller_node");
  first_id_ = static_cast<uint32_t>(readParam<int>(pnh_, "first_id"));
  count_ = static_cast<uint32_t>(readParam<int>(pnh_, "count"));
  configs_ = readControllerConfigs(NodeParams(pnh_));
  pool_ = std::make_shared<WorkerPool>(readThreads(NodeParams(pnh_)));
  const auto fast = ros::TransportHints().tcpNoDelay();
  commands_pub_ = nh_.advertise<CommandBatch>("swarm/commands", 8);
  status_pub_ = nh_.advertise<SwarmStatus>("swarm/status", 8);
  errors_pub_ = nh_.advertise<std_msgs::String>("swarm/errors", 8);
  sensors_sub_ = nh_.subscribe("world/sensors", 2, &ControllerRos::onSensors, this, fast);
  health_ = std::make_unique<HealthReporter>(
      nh_, pnh_, "controllers", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { fillHealth(s); },
      /*timer=*/true);
}

void ControllerRos::fillHealth(diagnostic_updater::DiagnosticStatusWrapper& s) {
  using Status = diagnostic_msgs::DiagnosticStatus;
  const std::string robots =
      "[" + std::to_string(first_id_) + ", " + std::to_string(first_id_ + served_count_) + ")";
  if (!refused_.empty())
    s.summary(Status::ERROR, refused_);
  else if (!started_)
    s.summary(Status::OK, "waiting for world/sensors");
  else
    s.summaryf(Status::OK, "run %u: %s for robots %s, tick %lu", run_, controller_.c_str(), robots.c_str(),
               static_cast<unsigned long>(last_tick_));
  s.add("controller", controller_);
  s.add("robots", started_ ? robots : std::string());
  s.add("run", run_);
  s.add("last tick", last_tick_);
  s.add("ticks answered", ticks_answered_);
  s.add("mean step [ms]", steps_since_report_ ? 1e3 * step_seconds_ / steps_since_report_ : 0.0);
  s.add("last world/sensors [s ago]", last_sensors_.isZero()
                                          ? std::string()
                                          : std::to_string((ros::WallTime::now() - last_sensors_).toSec()));
  s.add("threads", pool_->threads());
  s.add("jobs on one thread, cores contended [%]", pool_->percentAlone());
  s.add("world", world_);
  s.add("batches refused from another world", refused_batches_);
  // The last tick's status as on swarm/status, for any kind (built-in, plugin or Python): what the robots do.
  const SwarmStatus::Ptr status = status_msg_;
  s.add("in avoidance", status ? std::to_string(status->in_avoidance) : std::string());
  s.add("stalled", status ? std::to_string(status->stalled) : std::string());
  if (status)
    for (std::size_t i = 0; i < status->state_names.size() && i < status->state_counts.size(); ++i)
      s.add("state " + status->state_names[i], status->state_counts[i]);
  step_seconds_ = 0;
  steps_since_report_ = 0;
}

bool ControllerRos::startRun(const SensorBatch& msg) {
  try {
    controllerKind(msg.controller);
  } catch (const std::exception& e) {
    refused_ =
        "the world asks for controller '" + msg.controller + "', which this node cannot load: " + e.what();
    if (refused_log_.due()) ROS_ERROR("controller: %s", refused_.c_str());
    return false;
  }
  if (first_id_ >= msg.swarm_size) {
    refused_ = "~first_id " + std::to_string(first_id_) + " is beyond the swarm of " +
               std::to_string(msg.swarm_size) + " robots (valid: [0, " + std::to_string(msg.swarm_size - 1) +
               "])";
    if (refused_log_.due()) ROS_ERROR("controller: %s", refused_.c_str());
    return false;
  }
  if (msg.controller != controller_)
    ROS_INFO("controller: switching to %s for run %u", msg.controller.c_str(), msg.run);
  controller_ = msg.controller;
  const uint32_t count =
      count_ == 0 ? msg.swarm_size - first_id_ : std::min(count_, msg.swarm_size - first_id_);
  run_ = msg.run;
  started_ = true;
  failure_.clear();
  try {
    batch_ = makeController(controller_,
                            sharingWorld(configs_, Vec2(msg.nest_x, msg.nest_y),
                                         LineOfSight{msg.los_cell, static_cast<int>(msg.los_radius)}),
                            msg.seed, first_id_, count, pool_);
  } catch (const std::exception& e) {
    failed(msg.run, e.what());
    return false;
  }
  served_count_ = count;
  refused_.clear();
  last_tick_ = 0;
  commands_msg_.reset();
  constants_ = describeConstants(controller_, configs_);
  ROS_INFO("controller: run %u, %s for robots [%u, %u)", run_, controller_.c_str(), first_id_,
           first_id_ + count);
  return true;
}

void ControllerRos::failed(uint32_t run, const std::string& what) {
  if (failure_.empty()) ROS_ERROR("controller: run %u: %s", run, what.c_str());
  failure_ = what;
  batch_.reset();
  std_msgs::String msg;
  msg.data = ros::this_node::getName() + " (robots from " + std::to_string(first_id_) + "): " + what;
  errors_pub_.publish(msg);
}

bool ControllerRos::fromServedWorld(const std::string& sender) {
  // A world that went away may be followed by another (a new world_node): adopted once it is the only one.
  if (world_.empty() || sender == world_ || sensors_sub_.getNumPublishers() <= 1) {
    if (!world_.empty() && sender != world_)
      ROS_INFO("controller: now serving the world %s (%s is gone)", sender.c_str(), world_.c_str());
    world_ = sender;
    return true;
  }
  ++refused_batches_;
  if (refusal_log_.due())
    ROS_ERROR(
        "controller: refused world/sensors from %s: this controller serves the world %s (one world per "
        "graph); %lu batches refused",
        sender.c_str(), world_.c_str(), static_cast<unsigned long>(refused_batches_));
  return false;
}

void ControllerRos::onSensors(const ros::MessageEvent<const SensorBatch>& event) {
  if (!fromServedWorld(event.getPublisherName())) return;
  const SensorBatch::ConstPtr& msg = event.getMessage();
  last_sensors_ = ros::WallTime::now();
  // A new run: a world/reset, or a world started afresh (tick 0 again) while this node lives on.
  const bool restarted = started_ && msg->run == run_ && msg->tick == 0 && last_tick_ > 0;
  if (!started_ || msg->run != run_ || restarted) {
    if (!startRun(*msg)) return;
  } else if (!failure_.empty()) {
    failed(run_, failure_);  // the world offers the tick again: it may have missed the first word
    return;
  } else if (msg->tick == last_tick_ && commands_msg_) {  // the world offered this tick again
    status_pub_.publish(*status_msg_);
    commands_pub_.publish(commands_msg_);
    return;
  } else if (msg->tick < last_tick_) {
    return;  // stale
  }
  fromMsg(*msg, sensors_);
  try {
    batch_->step(msg->tick, sensors_, commands_, status_);
  } catch (const std::exception& e) {
    failed(msg->run, e.what());
    return;
  }
  last_tick_ = msg->tick;
  ++ticks_answered_;
  ++steps_since_report_;
  step_seconds_ += (ros::WallTime::now() - last_sensors_).toSec();

  // The run's identity names the constants: sent with the first answer of each run (tick 0 in lockstep).
  status_msg_ = boost::make_shared<SwarmStatus>(statusMsg(status_, commands_, msg->tick, msg->run,
                                                          msg->swarm_size, controller_, msg->header.stamp,
                                                          std::exchange(constants_, std::string())));
  commands_msg_ = boost::make_shared<CommandBatch>();
  commands_msg_->header.stamp = msg->header.stamp;
  commands_msg_->tick = msg->tick;
  commands_msg_->run = msg->run;
  toMsg(commands_, *commands_msg_);
  // The status goes by value (serialized even to a nodelet): roscpp numbers its header.seq, which the world
  // records, as across processes, so nodelet:=true records the same bag. The commands stay zero-copy.
  status_pub_.publish(*status_msg_);
  commands_pub_.publish(commands_msg_);
}

}  // namespace swarm_forage
