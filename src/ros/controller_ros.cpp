#include "swarm_forage/ros/controller_ros.hpp"

#include <algorithm>

#include "swarm_forage/ros/convert.hpp"
#include "swarm_forage/ros/params.hpp"

namespace swarm_forage {

namespace {
CrwConfig readCrw(const ros::NodeHandle& pnh) {
  CrwConfig c;
  c.wander_step = deg2rad(paramInRange(pnh, "crw/wander_step_deg", 5.0, 0.0, 180.0));
  c.wander_limit = deg2rad(paramInRange(pnh, "crw/wander_limit_deg", 5.0, 0.0, 180.0));
  c.wander_force = paramInRange(pnh, "crw/wander_force", c.wander_force, 0.001, 100.0);
  c.wander_free_scale = paramInRange(pnh, "crw/wander_free_scale", c.wander_free_scale, 0.001, 1.0);
  c.avoidance_force = paramInRange(pnh, "crw/avoidance_force", c.avoidance_force, 0.0, 100.0);
  c.phototaxis_force = paramInRange(pnh, "crw/phototaxis_force", c.phototaxis_force, 0.001, 100.0);
  c.nest_wander_ticks = static_cast<uint32_t>(paramInRange(pnh, "crw/nest_wander_ticks", 25, 0, 100000));
  c.min_explore_ticks = static_cast<uint32_t>(paramInRange(pnh, "crw/min_explore_ticks", 50, 0, 100000));
  c.drive.max_speed = paramInRange(pnh, "crw/max_speed", c.drive.max_speed, 0.001, 1.0);
  c.drive.soft_turn_max = deg2rad(paramInRange(pnh, "crw/soft_turn_max_deg", 15.0, 0.1, 179.9));
  c.drive.hard_turn_speed =
      paramInRange(pnh, "crw/hard_turn_speed", c.drive.hard_turn_speed, 0.001, c.drive.max_speed);
  c.validate();
  return c;
}
}  // namespace

ControllerRos::ControllerRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)>)
    : nh_(nh), pnh_(pnh) {
  controller_ = paramOneOf(pnh_, "controller", "crw", controllerNames());
  first_id_ = static_cast<uint32_t>(paramInRange(pnh_, "first_id", 0, 0, 10000000));
  count_ = static_cast<uint32_t>(paramInRange(pnh_, "count", 0, 0, 10000000));
  crw_ = readCrw(pnh_);
  const auto fast = ros::TransportHints().tcpNoDelay();
  commands_pub_ = nh_.advertise<CommandBatch>("swarm/commands", 8);
  status_pub_ = nh_.advertise<SwarmStatus>("swarm/status", 8);
  sensors_sub_ = nh_.subscribe("world/sensors", 2, &ControllerRos::onSensors, this, fast);
}

bool ControllerRos::startRun(const SensorBatch& msg) {
  const auto& names = controllerNames();
  if (std::find(names.begin(), names.end(), msg.controller) == names.end()) {
    ROS_ERROR_THROTTLE(5, "controller: the world asks for controller '%s', which this build lacks",
                       msg.controller.c_str());
    return false;
  }
  if (first_id_ >= msg.swarm_size) {
    ROS_ERROR_THROTTLE(5, "controller: ~first_id %u is beyond the swarm of %u robots (valid: [0, %u])",
                       first_id_, msg.swarm_size, msg.swarm_size - 1);
    return false;
  }
  if (msg.controller != controller_)
    ROS_INFO("controller: switching to %s for run %u", msg.controller.c_str(), msg.run);
  controller_ = msg.controller;
  const uint32_t count =
      count_ == 0 ? msg.swarm_size - first_id_ : std::min(count_, msg.swarm_size - first_id_);
  batch_ = std::make_unique<CrwBatch>(crw_, msg.seed, first_id_, count);
  run_ = msg.run;
  started_ = true;
  ROS_INFO("controller: run %u, %s for robots [%u, %u)", run_, controller_.c_str(), first_id_,
           first_id_ + count);
  return true;
}

void ControllerRos::onSensors(const SensorBatch::ConstPtr& msg) {
  if (!started_ || msg->run != run_) {
    if (!startRun(*msg)) return;
  } else if (msg->tick == last_tick_ && commands_msg_) {  // the world offered this tick again
    status_pub_.publish(status_msg_);
    commands_pub_.publish(commands_msg_);
    return;
  } else if (msg->tick < last_tick_) {
    return;  // stale
  }
  fromMsg(*msg, sensors_);
  batch_->step(msg->tick, sensors_, commands_, status_);
  last_tick_ = msg->tick;

  status_msg_ = boost::make_shared<SwarmStatus>();
  status_msg_->header.stamp = msg->header.stamp;
  status_msg_->tick = msg->tick;
  status_msg_->run = msg->run;
  status_msg_->first_id = commands_.first_id;
  status_msg_->count = static_cast<uint32_t>(commands_.size());
  status_msg_->swarm_size = msg->swarm_size;
  status_msg_->controller = controller_;
  toMsg(status_, *status_msg_);
  commands_msg_ = boost::make_shared<CommandBatch>();
  commands_msg_->header.stamp = msg->header.stamp;
  commands_msg_->tick = msg->tick;
  commands_msg_->run = msg->run;
  toMsg(commands_, *commands_msg_);
  status_pub_.publish(status_msg_);
  commands_pub_.publish(commands_msg_);
}

}  // namespace swarm_forage
