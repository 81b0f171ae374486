#include "swarm_forage/ros/controller_ros.hpp"

#include <algorithm>
#include <utility>

#include "swarm_forage/core/controller_parameters.hpp"
#include "swarm_forage/ros/convert.hpp"
#include "swarm_forage/ros/params.hpp"

namespace swarm_forage {

namespace {
// Reads a config from ~<section>/<name> through the core's parameter lists (defaults: the core's, which
// equal the YAML files); validate() then names the field and its range. Angles are read in degrees.
struct Reader {
  const ros::NodeHandle& pnh;
  std::string prefix;
  void number(const char* name, double& v) const { v = param<double>(pnh, prefix + name, v); }
  void count(const char* name, uint32_t& v) const {
    v = static_cast<uint32_t>(paramInRange(pnh, prefix + name, static_cast<int>(v), 0, 2147483647));
  }
  void degrees(const char* name, double& radians) const {
    radians = deg2rad(param<double>(pnh, prefix + name, radians * 180.0 / kPi));
  }
  void choice(const char* name, bool& flag, const char* off, const char* on) const {
    flag = paramOneOf(pnh, prefix + name, flag ? on : off, {off, on}) == on;
  }
};

/// A typo in a controller YAML (`widht`, `wander_forse`) would otherwise leave a default in force unseen.
void rejectUnknownKeys(const ros::NodeHandle& pnh) {
  for (const std::string& section : parameterSections()) {
    XmlRpc::XmlRpcValue values;
    if (!pnh.getParam(section, values)) continue;
    const std::vector<std::string> valid = parameterNames(section);
    std::string list;
    for (const auto& n : valid) list += (list.empty() ? "" : ", ") + n;
    if (values.getType() != XmlRpc::XmlRpcValue::TypeStruct)
      throw ParameterError("~" + section + " must be a map of " + section + " constants (" + list + ")");
    for (auto it = values.begin(); it != values.end(); ++it)
      if (std::find(valid.begin(), valid.end(), it->first) == valid.end())
        throw ParameterError("~" + section + "/" + it->first + " is not a " + section +
                             " constant (a typo in config/controllers/" + section +
                             ".yaml?); valid keys: " + list);
  }
}

ControllerConfigs readConfigs(const ros::NodeHandle& pnh) {
  rejectUnknownKeys(pnh);
  ControllerConfigs c;
  visitCrwParameters(c.crw, Reader{pnh, "crw/"});
  c.dpo.explore = c.crw;
  visitDpoParameters(c.dpo, Reader{pnh, "dpo/"});
  c.gp_dpo.dpo = c.dpo;
  visitGpDpoParameters(c.gp_dpo, Reader{pnh, "gp_dpo/"});
  try {
    c.gp_dpo.validate();  // validates dpo and crw too
  } catch (const ParameterError& e) {
    throw ParameterError("~" + std::string(e.what()));  // core messages name the YAML key
  }
  return c;
}

}  // namespace

ControllerRos::ControllerRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)>)
    : nh_(nh), pnh_(pnh) {
  controller_ = paramOneOf(pnh_, "controller", "crw", controllerNames());
  first_id_ = static_cast<uint32_t>(paramInRange(pnh_, "first_id", 0, 0, 10000000));
  count_ = static_cast<uint32_t>(paramInRange(pnh_, "count", 0, 0, 10000000));
  configs_ = readConfigs(pnh_);
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
  batch_ = makeController(controller_,
                          sharingWorld(configs_, Vec2(msg.nest_x, msg.nest_y),
                                       LineOfSight{msg.los_cell, static_cast<int>(msg.los_radius)}),
                          msg.seed, first_id_, count);
  run_ = msg.run;
  started_ = true;
  last_tick_ = 0;
  commands_msg_.reset();
  constants_ = describeConstants(controller_, configs_);
  ROS_INFO("controller: run %u, %s for robots [%u, %u)", run_, controller_.c_str(), first_id_,
           first_id_ + count);
  return true;
}

void ControllerRos::onSensors(const SensorBatch::ConstPtr& msg) {
  // A new run: a world/reset, or a world started afresh (tick 0 again) while this node lives on.
  const bool restarted = started_ && msg->run == run_ && msg->tick == 0 && last_tick_ > 0;
  if (!started_ || msg->run != run_ || restarted) {
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
  // The run's identity names the constants: sent with the first answer of each run (tick 0 in lockstep).
  if (!constants_.empty()) status_msg_->constants = std::exchange(constants_, std::string());
  commands_msg_ = boost::make_shared<CommandBatch>();
  commands_msg_->header.stamp = msg->header.stamp;
  commands_msg_->tick = msg->tick;
  commands_msg_->run = msg->run;
  toMsg(commands_, *commands_msg_);
  status_pub_.publish(status_msg_);
  commands_pub_.publish(commands_msg_);
}

}  // namespace swarm_forage
