#pragma once
// controller_node: a batch of robot controllers for the robot ids [~first_id, ~first_id + ~count):
// one world/sensors batch in, one swarm/commands and one swarm/status out per tick.
#include <ros/ros.h>
#include <swarm_forage/CommandBatch.h>
#include <swarm_forage/SensorBatch.h>
#include <swarm_forage/SwarmStatus.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/ros/nodes/health.hpp"

namespace swarm_forage {

class ControllerRos {
 public:
  /// Reads and validates ~parameters (throws ParameterError); callbacks run on nh's queue.
  ControllerRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish = {});
  /// Its private parameters (known_params.cpp): any other is refused at start-up.
  static std::vector<std::string> parameterNames();

 private:
  void onSensors(const ros::MessageEvent<const SensorBatch>& event);
  /// True for a batch of the world served; a second world's is refused (logged) while the first lives.
  bool fromServedWorld(const std::string& sender);
  /// A fresh batch for a new run (or a new controller kind); false when the range is not served.
  bool startRun(const SensorBatch& msg);
  /// The batch threw: tells the world on swarm/errors (again at each offer of the run's ticks) and serves
  /// no more of run `run`.
  void failed(uint32_t run, const std::string& what);
  void fillHealth(diagnostic_updater::DiagnosticStatusWrapper& s);

  ros::NodeHandle nh_, pnh_;
  ros::Subscriber sensors_sub_;
  ros::Publisher commands_pub_, status_pub_, errors_pub_;
  std::string controller_;
  uint32_t first_id_ = 0, count_ = 0;  // count 0: every robot from first_id on
  ControllerConfigs configs_;

  std::unique_ptr<ControllerBatch> batch_;
  std::shared_ptr<WorkerPool> pool_;  // ~threads
  bool started_ = false;
  std::string world_;                                 // the node whose world/sensors this controller answers
  uint64_t refused_batches_ = 0;                      // from another world
  WallThrottle refusal_log_{5.0}, refused_log_{5.0};  // wall time: /clock stands still at tick 0
  uint32_t run_ = 0;
  uint64_t last_tick_ = 0;
  std::string constants_;  // describeConstants() of the run, until the first status carries it
  SensorData sensors_;
  CommandData commands_;
  ControllerStatus status_;
  CommandBatch::Ptr commands_msg_;
  SwarmStatus::Ptr status_msg_;

  // Health (/diagnostics): what is served, how fast, and why a batch was refused.
  uint32_t served_count_ = 0;
  uint64_t ticks_answered_ = 0, steps_since_report_ = 0;
  double step_seconds_ = 0;  // wall time in batch steps since the last report
  ros::WallTime last_sensors_;
  std::string refused_;  // why the world's last batch could not be served ("" when it could)
  std::string failure_;  // what the batch threw in run run_ ("" while it works)
  std::unique_ptr<HealthReporter> health_;
};

}  // namespace swarm_forage
