#pragma once
// world_node: owns the core World, steps it in lockstep with the controllers and the environment
// (or in real time), publishes every world topic and records the run to a bag.
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <swarm_forage/CommandBatch.h>
#include <swarm_forage/Info.h>
#include <swarm_forage/Reset.h>
#include <swarm_forage/RunInfo.h>
#include <swarm_forage/SensorBatch.h>
#include <swarm_forage/SwarmStatus.h>
#include <swarm_forage/Throttle.h>
#include <swarm_forage/WorldPaceConfig.h>
#include <visualization_msgs/MarkerArray.h>

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <thread>

#include "swarm_forage/core/run/range_coverage.hpp"
#include "swarm_forage/core/world/world.hpp"
#include "swarm_forage/ros/reconfigure.hpp"
#include "swarm_forage/ros/run_recorder.hpp"
#include "swarm_forage/ros/world_frames.hpp"
#include "swarm_forage/ros/world_guard.hpp"
#include "swarm_forage/ros/world_health.hpp"

namespace swarm_forage {

/// The range of ~real_time_factor, at start-up and live.
constexpr double kMinRealTimeFactor = 0.001, kMaxRealTimeFactor = 1000.0;

class WorldRos {
 public:
  /// Reads and validates ~parameters (throws ParameterError), sets up topics and services and
  /// starts stepping on a thread of its own; `finish(exit_code)` is called when stepping ends.
  WorldRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish);
  ~WorldRos();
  /// Its private parameters (known_params.cpp): any other is refused at start-up.
  static std::vector<std::string> parameterNames();

 private:
  enum class Mode { kLockstep, kRealtime };
  /// Runs until shut down (or the end of the run with ~exit_when_done); the node's exit code.
  int run();
  /// "" once every peer is there, else what is still missing after ~startup_timeout.
  std::string waitForPeers();
  void beginRun();
  /// world/run_info of the current run (with the constants the controllers reported), recorded first
  /// in its bag; "" or why the controllers' answers cannot make one run.
  std::string publishRunInfo();
  /// Steps the run to its end; "" when it reached its last tick, else why it stopped.
  std::string stepRun();
  /// Records how the run ended (world/run_end, in the bag and latched, and ~outcome), closes the bag
  /// and logs "run K finished" or "run K stopped at tick T of M (reason)". False when the run is not a
  /// finished record (stopped early, or its bag could not be given its name).
  bool endRun(const std::string& stopped);
  /// "" once tick `tick` has every reply, else why not within ~step_timeout.
  std::string awaitReplies(uint64_t tick);
  /// Realtime: serves callbacks until `deadline`; "" or why the run cannot go on (a silent controller).
  std::string waitRealtime(uint64_t tick, ros::WallTime deadline);
  std::string shutdownReason(uint64_t tick) const;
  /// This tick's replies still missing, and from whom.
  std::string missingReplies() const;
  void publishTick(uint64_t tick);
  void publishSensors(uint64_t tick);
  void publishAfterStep(uint64_t tick, const StepResult& result);
  void publishSnapshots(uint64_t tick, bool publish, bool record);
  void publishCachesOnChange(uint64_t tick);
  /// world/markers, at most ~markers_rate a wall second and only while someone subscribes.
  void publishMarkers(uint64_t tick);
  RunInfo runInfo() const;

  void onCommands(const ros::MessageEvent<const CommandBatch>& event);
  void onStatus(const ros::MessageEvent<const SwarmStatus>& event);
  void onThrottle(const ros::MessageEvent<const Throttle>& event);
  bool onReset(Reset::Request& req, Reset::Response& res);
  bool onInfo(Info::Request& req, Info::Response& res);
  /// A live ~real_time_factor (realtime mode only; checked like the start-up one).
  WorldPaceConfig repace(const WorldPaceConfig& requested);

  ros::NodeHandle nh_, pnh_;
  ros::CallbackQueue queue_;  // served only by the stepping thread: callbacks need no locks
  ros::Publisher clock_pub_, sensors_pub_, performance_pub_, robots_pub_, blocks_pub_, caches_pub_, nest_pub_,
      info_pub_, end_pub_, markers_pub_, provenance_pub_;
  ros::Subscriber commands_sub_, status_sub_, throttle_sub_;
  ros::ServiceServer reset_srv_, info_srv_;
  std::unique_ptr<WorldFrames> frames_;  // tf

  // Parameters.
  WorldConfig config_;
  std::string controller_;
  Mode mode_ = Mode::kLockstep;
  uint64_t ticks_ = 0;
  uint64_t ns_per_tick_ = 0;
  std::atomic<double> real_time_factor_{1.0};  // set live by dynamic_reconfigure (pnh's thread)
  double step_timeout_ = 5.0, startup_timeout_ = 30.0;
  int publish_every_ = 25, record_every_ = 250, wait_for_subscribers_ = 0;
  double markers_rate_ = 5.0;  // world/markers per wall second (0: never)
  ros::WallTime markers_last_;
  uint64_t markers_built_ = 0;  // on /diagnostics: none while nobody subscribes
  double markers_seconds_ = 0;  // wall time the last world/markers took to build and publish
  bool use_environment_ = true, exit_when_done_ = false;
  std::string bag_path_, bag_dir_, outcome_path_, compression_, label_;
  bool overwrite_ = false;
  ExistingBag existing_ = ExistingBag::kRefuse;  // what closing a record does when its name is taken

  // Run state.
  std::unique_ptr<World> world_;
  std::shared_ptr<WorkerPool> pool_;  // ~threads
  uint32_t run_ = 0;
  SensorData sensors_;
  visualization_msgs::MarkerArray markers_;  // refilled in place
  CommandData commands_;
  RangeCoverage commands_seen_{"swarm/commands"}, status_seen_{"swarm/status"};
  std::vector<SwarmStatus> status_;               // this tick's, recorded in first-id order
  std::map<std::string, std::string> constants_;  // controller node -> the constants it reported
  std::string range_error_;                       // a split of the swarm that cannot work, once seen
  std::map<std::string, std::pair<ros::WallTime, std::string>> heard_;  // node -> (last answer, ranges)
  std::optional<Throttle> throttle_;
  std::optional<Throttle> recorded_throttle_;  // the throttle last recorded (recordThrottle)
  std::string throttle_sender_;
  uint64_t awaited_tick_ = 0;
  struct PendingReset {
    uint32_t seed, n_robots;
    std::string controller;
  };
  std::optional<PendingReset> pending_reset_;
  RunRecorder recorder_;
  std::pair<bool, std::size_t> cache_state_{false, 0};  // last published (exists, blocks)
  ros::WallTime run_started_;
  bool info_sent_ = false;
  RunInfo info_;

  std::unique_ptr<Reconfigurable<WorldPaceConfig>> pace_;
  std::unique_ptr<WorldHealth> health_;  // /diagnostics
  std::unique_ptr<WorldGuard> guard_;    // one world per graph

  std::thread thread_;
  std::atomic<bool> stop_{false};
};

}  // namespace swarm_forage
