#pragma once
// world_node: the run engine (core/run/run.hpp) as a node. Its ports are topics: world/sensors out and
// swarm/commands + swarm/status back (the lockstep barrier, or the latest answers in realtime), the
// condition from environment/throttle; its sinks are the world topics, a bag and an outcome file.
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <swarm_forage/CommandBatch.h>
#include <swarm_forage/Info.h>
#include <swarm_forage/NoiseConfig.h>
#include <swarm_forage/PopulationRatesConfig.h>
#include <swarm_forage/Reset.h>
#include <swarm_forage/SwarmStatus.h>
#include <swarm_forage/Throttle.h>
#include <swarm_forage/WorldPaceConfig.h>

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "swarm_forage/core/run/range_coverage.hpp"
#include "swarm_forage/core/run/run.hpp"
#include "swarm_forage/ros/params/reconfigure.hpp"
#include "swarm_forage/ros/runs/bag_sink.hpp"
#include "swarm_forage/ros/world_node/world_frames.hpp"
#include "swarm_forage/ros/world_node/world_guard.hpp"
#include "swarm_forage/ros/world_node/world_health.hpp"
#include "swarm_forage/ros/world_node/world_markers.hpp"

namespace swarm_forage {

/// cfg/Noise.cfg's fields (<device>_model, <device>_level, ground_level) from a noise, and back.
NoiseConfig noiseConfig(const SaaNoise& noise);
SaaNoise noiseOf(const NoiseConfig& config);

class WorldRos : public ControllerPort, public EnvironmentPort, public RunSink {
 public:
  /// Reads and validates ~parameters (throws ParameterError), sets up topics and services and
  /// starts stepping on a thread of its own; `finish(exit_code)` is called when stepping ends.
  WorldRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish);
  ~WorldRos() override;
  /// Its private parameters (known_params.cpp): any other is refused at start-up.
  static std::vector<std::string> parameterNames();

 private:
  /// Runs until shut down (or the end of the run with ~exit_when_done); the node's exit code.
  int run();
  /// "" once every peer is there, else what is still missing after ~startup_timeout.
  std::string waitForPeers();
  /// A new run (run_ + 1) for a pending world/reset.
  void reset();
  /// Builds `run`'s world (throws ParameterError for an invalid one); its ports and sinks are this node's.
  void newRun(const RunDescription& run);
  /// "" or why the run must stop before `tick` (a world/reset, a shutdown).
  /// Also applies a live change of the population rates at the start of `tick` (the stepping thread).
  StepOutcome interrupted(uint64_t tick);
  std::string shutdownReason(uint64_t tick) const;

  // ControllerPort and EnvironmentPort: the topics (world_replies.cpp).
  void begin(const RunDescription& run, const World& world) override;
  StepOutcome decide(uint64_t tick, const World& world, const SensorData& sensors) override;
  const CommandData& commands() const override { return commands_; }
  const std::vector<StatusRecord>& status() const override { return status_; }
  std::optional<ConditionSample> condition(uint64_t) override { return throttle_; }
  std::string awaitReplies(uint64_t tick, const World& world, const SensorData& sensors);
  /// Realtime: serves callbacks until `deadline`; "" or why the run cannot go on (a silent controller).
  std::string waitRealtime(uint64_t tick, ros::WallTime deadline);
  /// This tick's replies still missing, and from whom.
  std::string missingReplies() const;
  void publishSensors(uint64_t tick, const World& world, const SensorData& sensors);
  void onCommands(const ros::MessageEvent<const CommandBatch>& event);
  void onStatus(const ros::MessageEvent<const SwarmStatus>& event);
  void onThrottle(const ros::MessageEvent<const Throttle>& event);
  void onControllerError(const std_msgs::String& error);

  // RunSink: the world topics, /diagnostics and the log (world_topics.cpp).
  bool isRecord() const override { return false; }
  bool wantsSnapshot() const override;
  void begin(const RunDescription& run, const std::string& label) override;
  void snapshot(uint64_t tick, const SensorData& sensors, const BlockField& blocks) override;
  void caches(uint64_t tick, const StaticCache& cache) override;
  void identityFixed(const RunDescription& run) override;
  void condition(uint64_t, const ConditionSample&) override {}       // environment_node publishes it
  void noiseChanged(uint64_t tick, const SaaNoise& noise) override;  // world/noise
  void population(const PopulationRecord& p) override;
  void stepped(const std::vector<StatusRecord>& status, const PerformanceRecord& performance) override;
  void end(RunEndRecord& end) override;

  // Services and the live knob (world_services.cpp).
  bool onReset(Reset::Request& req, Reset::Response& res);
  bool onInfo(Info::Request& req, Info::Response& res);
  /// A live ~real_time_factor (realtime mode only; checked like the start-up one).
  WorldPaceConfig repace(const WorldPaceConfig& requested);
  /// A live noise (realtime mode only; checked like the start-up one), applied from the next tick on.
  NoiseConfig renoise(const NoiseConfig& requested);
  /// The stepping thread, between ticks: hands a live noise change to the run.
  void applyNoiseChange();

  ros::NodeHandle nh_, pnh_;
  ros::CallbackQueue queue_;       // served only by the stepping thread: callbacks need no locks
  ros::Publisher population_pub_;  // advertised only for a world with population dynamics
  ros::Publisher clock_pub_, sensors_pub_, performance_pub_, robots_pub_, blocks_pub_, caches_pub_, nest_pub_,
      info_pub_, end_pub_, provenance_pub_, noise_pub_;
  ros::Subscriber commands_sub_, status_sub_, throttle_sub_, errors_sub_;
  ros::ServiceServer reset_srv_, info_srv_;
  std::unique_ptr<WorldFrames> frames_;  // tf

  // Parameters.
  bool lockstep_ = true;
  uint64_t ns_per_tick_ = 0;
  std::atomic<double> real_time_factor_{1.0};  // set live by dynamic_reconfigure (pnh's thread)
  double step_timeout_ = 5.0, startup_timeout_ = 30.0;
  int wait_for_subscribers_ = 0;
  bool use_environment_ = true, exit_when_done_ = false;
  RunSchedule schedule_;
  std::string label_;

  // Runs, and the replies to the current tick.
  std::shared_ptr<WorkerPool> pool_;  // ~threads
  std::unique_ptr<BagSink> bag_;
  std::unique_ptr<OutcomeFile> outcome_;
  std::unique_ptr<Run> run_;
  uint32_t run_no_ = 0;
  struct PendingReset {
    uint32_t seed, n_robots;
    std::string controller;
  };
  std::optional<PendingReset> pending_reset_;
  ros::WallTime run_started_, next_;
  CommandData commands_;
  RangeCoverage commands_seen_{"swarm/commands"}, status_seen_{"swarm/status"};
  std::vector<StatusRecord> status_;  // this tick's
  std::string range_error_;           // a split of the swarm that cannot work, once seen
  std::map<std::string, std::pair<ros::WallTime, std::string>> heard_;  // node -> (last answer, ranges)
  std::optional<ConditionSample> throttle_;
  std::string throttle_sender_;
  uint64_t awaited_tick_ = 0;
  std::unique_ptr<MarkerPublisher> markers_;

  std::unique_ptr<Reconfigurable<WorldPaceConfig>> pace_;
  /// Population rates, live (~population/..., realtime runs with population dynamics): checked in the
  /// server's thread, applied by the stepping thread at the next tick.
  PopulationRatesConfig rerate(const PopulationRatesConfig& requested);
  std::mutex rates_mutex_;
  std::optional<PopulationConfig> pending_rates_;
  PopulationConfig rates_now_;  // the last rates set (start-up or live)
  std::unique_ptr<Reconfigurable<PopulationRatesConfig>> rates_;
  std::unique_ptr<Reconfigurable<NoiseConfig>> noise_knob_;
  std::mutex noise_mutex_;  // the knob's thread sets, the stepping thread takes:
  SaaNoise live_noise_;     // the noise in force or about to be
  bool noise_pending_ = false;
  std::unique_ptr<WorldHealth> health_;  // /diagnostics
  std::unique_ptr<WorldGuard> guard_;    // one world per graph

  std::thread thread_;
  std::atomic<bool> stop_{false};
};

}  // namespace swarm_forage
