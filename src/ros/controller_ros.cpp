#include "swarm_forage/ros/controller_ros.hpp"

#include <algorithm>

#include "swarm_forage/ros/convert.hpp"
#include "swarm_forage/ros/params.hpp"

namespace swarm_forage {

namespace {
// Each reader fills a config from ~<kind>/<field> (defaults: the core's, which equal the YAML files);
// validate() then names the field and its range. Angles are read in degrees.
struct Reader {
  const ros::NodeHandle& pnh;
  std::string prefix;
  void operator()(const char* name, double& v) const { v = param<double>(pnh, prefix + name, v); }
  void operator()(const char* name, uint32_t& v) const {
    const int read = param<int>(pnh, prefix + name, static_cast<int>(v));
    if (read < 0)
      throw ParameterError("~" + prefix + name + " must be >= 0 (got " + std::to_string(read) + ")");
    v = static_cast<uint32_t>(read);
  }
  void degrees(const char* name, double& radians) const {
    radians = deg2rad(param<double>(pnh, prefix + name, radians * 180.0 / kPi));
  }
};

CrwConfig readCrw(const ros::NodeHandle& pnh) {
  CrwConfig c;
  const Reader read{pnh, "crw/"};
  read.degrees("wander_step_deg", c.wander_step);
  read.degrees("wander_limit_deg", c.wander_limit);
  read("wander_force", c.wander_force);
  read("wander_free_scale", c.wander_free_scale);
  read("avoidance_force", c.avoidance_force);
  read("phototaxis_force", c.phototaxis_force);
  read("nest_wander_ticks", c.nest_wander_ticks);
  read("min_explore_ticks", c.min_explore_ticks);
  read("max_speed", c.drive.max_speed);
  read.degrees("soft_turn_max_deg", c.drive.soft_turn_max);
  read("hard_turn_speed", c.drive.hard_turn_speed);
  return c;
}

DpoConfig readDpo(const ros::NodeHandle& pnh, const CrwConfig& explore) {
  DpoConfig c;
  c.explore = explore;
  const Reader read{pnh, "dpo/"};
  read("pheromone_initial", c.pheromone_initial);
  read("pheromone_decay", c.pheromone_decay);
  read("new_place_distance", c.new_place_distance);
  read("exclusion_radius", c.exclusion_radius);
  read("arrival_tolerance", c.arrival_tolerance);
  read("slowing_radius", c.slowing_radius);
  read("vector_force", c.vector_force);
  read("collision_window", c.collision_window);
  read("recovery_spin_ticks", c.recovery_spin_ticks);
  read("recovery_spin_speed", c.recovery_spin_speed);
  read("recovery_straight_ticks", c.recovery_straight_ticks);
  read("recovery_straight_speed", c.recovery_straight_speed);
  return c;
}

GpDpoConfig readGpDpo(const ros::NodeHandle& pnh, const DpoConfig& dpo) {
  GpDpoConfig c;
  c.dpo = dpo;
  c.time_varying = paramOneOf(pnh, "gp_dpo/estimates", "ideal", {"ideal", "time_varying"}) == "time_varying";
  const Reader read{pnh, "gp_dpo/"};
  read("ideal_generalist_min", c.ideal_generalist_min);
  read("ideal_generalist_max", c.ideal_generalist_max);
  read("ideal_subtask_min", c.ideal_subtask_min);
  read("ideal_subtask_max", c.ideal_subtask_max);
  read("ideal_partition_reactivity", c.ideal_partition_reactivity);
  read("varying_generalist_min", c.varying_generalist_min);
  read("varying_generalist_max", c.varying_generalist_max);
  read("varying_subtask_min", c.varying_subtask_min);
  read("varying_subtask_max", c.varying_subtask_max);
  read("varying_partition_reactivity", c.varying_partition_reactivity);
  read("ema_weight", c.ema_weight);
  read("partition_initial", c.partition_initial);
  read("subtask_reactivity", c.subtask_reactivity);
  read("subtask_offset", c.subtask_offset);
  read("abort_reactivity", c.abort_reactivity);
  read("abort_offset", c.abort_offset);
  return c;
}

ControllerConfigs readConfigs(const ros::NodeHandle& pnh) {
  ControllerConfigs c;
  c.crw = readCrw(pnh);
  c.dpo = readDpo(pnh, c.crw);
  c.gp_dpo = readGpDpo(pnh, c.dpo);
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
