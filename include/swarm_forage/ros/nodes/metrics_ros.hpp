#pragma once
// metrics_node: turns per-tick performance (with the throttle V applied) and interference into per-interval
// P, p, n_ca and s (docs/design-model.md, One metrics path) on metrics/performance and, against a library of
// finished runs, the paper's e, Z, R and A on metrics/scalability, metrics/self_organization,
// metrics/reactivity and metrics/adaptability, and for a run with noise or population dynamics its robustness
// on metrics/robustness (docs/robustness-measures.md): a running value every sample and the final one at the
// run's end. The same from a live run and from `rosbag play --clock`. metrics/compute turns a directory of
// bags into tables.
#include <ros/ros.h>
#include <swarm_forage/Compute.h>
#include <swarm_forage/NoiseChange.h>
#include <swarm_forage/Performance.h>
#include <swarm_forage/Population.h>
#include <swarm_forage/RunEnd.h>
#include <swarm_forage/RunInfo.h>
#include <swarm_forage/SwarmStatus.h>
#include <swarm_forage/Throttle.h>

#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <set>

#include "swarm_forage/core/metrics/run_follower.hpp"
#include "swarm_forage/ros/nodes/health.hpp"
#include "swarm_forage/ros/runs/run_bag.hpp"

namespace swarm_forage {

class MetricsRos : private RunFollower::Listener {
 public:
  /// `finish(0)` is called after the final sample of a run when ~exit_on_final is true.
  MetricsRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish = {});
  /// Its private parameters (known_params.cpp): any other is refused at start-up.
  static std::vector<std::string> parameterNames();

 private:
  void onRunInfo(const ros::MessageEvent<const RunInfo>& event);
  void onRunEnd(const ros::MessageEvent<const RunEnd>& event);
  void onPerformance(const ros::MessageEvent<const Performance>& event);
  /// True for a message of the world followed (or of the only world left); a second world's is refused.
  bool fromFollowedWorld(const std::string& sender, const ros::Subscriber& sub, const char* topic);
  void onStatus(const ros::MessageEvent<const SwarmStatus>& event);
  void onThrottle(const Throttle::ConstPtr& msg);
  void onNoise(const NoiseChange::ConstPtr& msg);
  void onPopulation(const Population::ConstPtr& msg);  // `changed`: no reference from then on
  bool onCompute(Compute::Request& req, Compute::Response& res);
  // What the follower finds (RunFollower::Listener).
  void described(const FollowedRun& run) override;
  void sample(const FollowedRun& run, const IntervalSample& s, uint64_t stamp_ns) override;
  void warn(const std::string& what) override;
  void error(const std::string& what) override;
  void publishMetrics(const FollowedRun& run, const IntervalSample& s, const ros::Time& stamp);
  void scanLibrary();
  void fillHealth(diagnostic_updater::DiagnosticStatusWrapper& s);

  ros::NodeHandle nh_, pnh_;
  ros::Subscriber info_sub_, end_sub_, performance_sub_, status_sub_, throttle_sub_, noise_sub_,
      population_sub_;
  ros::Publisher interval_pub_, scalability_pub_, self_organization_pub_, reactivity_pub_, adaptability_pub_,
      robustness_pub_;
  ros::ServiceServer compute_srv_;
  std::function<void(int)> finish_;
  uint32_t interval_ = 1000;
  bool exit_on_final_ = false;
  Definitions definitions_ = Definitions::kPaper;
  std::optional<std::size_t> band_;
  std::string library_dir_;
  std::ofstream csv_;

  std::unique_ptr<RunFollower> follower_;
  std::string world_;  // the node whose world/performance, run_info and run_end are followed
  WallThrottle refusal_log_{5.0};
  RunLibrary library_;
  RunBagCache bags_{1000};
  std::string reported_missing_;            // the last missing-reference warning, logged once per run
  std::set<std::string> reported_library_;  // library problems already logged
  uint64_t samples_published_ = 0;
  HealthThresholds behind_;                 // ~diag_behind_warn, ~diag_behind_error: ticks not yet complete
  std::unique_ptr<HealthReporter> health_;  // /diagnostics
};

}  // namespace swarm_forage
