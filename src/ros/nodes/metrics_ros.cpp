#include "swarm_forage/ros/nodes/metrics_ros.hpp"

#include <swarm_forage/IntervalPerformance.h>

#include <filesystem>

#include "swarm_forage/ros/messages/metrics_messages.hpp"
#include "swarm_forage/ros/params/known_params.hpp"
#include "swarm_forage/ros/params/params.hpp"
#include "swarm_forage/ros/runs/follower_messages.hpp"
#include "swarm_forage/ros/runs/run_tables.hpp"

namespace swarm_forage {

MetricsRos::MetricsRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish)
    : nh_(nh), pnh_(pnh), finish_(std::move(finish)) {
  refuseUnknownParams(pnh_, parameterNames(), "metrics_node");
  interval_ = static_cast<uint32_t>(readParam<int>(pnh_, "sample_interval"));
  exit_on_final_ = readParam<bool>(pnh_, "exit_on_final");
  definitions_ = parseDefinitions(readParam<std::string>(pnh_, "definitions"));
  const int band = readParam<int>(pnh_, "dtw_band");
  if (band > 0) band_ = static_cast<std::size_t>(band);
  library_dir_ = readParam<std::string>(pnh_, "library");
  bags_ = RunBagCache(interval_);
  follower_ =
      std::make_unique<RunFollower>(interval_, RunFollower::Mode::kLive, static_cast<Listener*>(this));
  if (!library_dir_.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(library_dir_, ec);
    if (ec || !std::filesystem::is_directory(library_dir_))
      throw ParameterError("~library '" + library_dir_ + "' is not a directory that can be created or read");
    scanLibrary();
  }
  const std::string csv = readParam<std::string>(pnh_, "csv");
  if (!csv.empty()) {
    csv_.open(csv);
    if (!csv_) throw ParameterError("~csv '" + csv + "' cannot be written");
    csv_ << kSampleCsvHeader << std::flush;
  }
  // Replays publish as fast as asked: queues deep enough that no tick is dropped.
  const auto fast = ros::TransportHints().tcpNoDelay();
  interval_pub_ = nh_.advertise<IntervalPerformance>("metrics/performance", 100);
  scalability_pub_ = nh_.advertise<ScalabilityMetric>("metrics/scalability", 100);
  self_organization_pub_ = nh_.advertise<SelfOrganizationMetric>("metrics/self_organization", 100);
  reactivity_pub_ = nh_.advertise<FlexibilityMetric>("metrics/reactivity", 100);
  adaptability_pub_ = nh_.advertise<FlexibilityMetric>("metrics/adaptability", 100);
  robustness_pub_ = nh_.advertise<Robustness>("metrics/robustness", 100);
  compute_srv_ = nh_.advertiseService("metrics/compute", &MetricsRos::onCompute, this);
  info_sub_ = nh_.subscribe("world/run_info", 100, &MetricsRos::onRunInfo, this, fast);
  end_sub_ = nh_.subscribe("world/run_end", 100, &MetricsRos::onRunEnd, this, fast);
  performance_sub_ = nh_.subscribe("world/performance", 100000, &MetricsRos::onPerformance, this, fast);
  status_sub_ = nh_.subscribe("swarm/status", 100000, &MetricsRos::onStatus, this, fast);
  throttle_sub_ = nh_.subscribe("environment/throttle", 1000, &MetricsRos::onThrottle, this, fast);
  noise_sub_ = nh_.subscribe("world/noise", 100, &MetricsRos::onNoise, this, fast);
  population_sub_ = nh_.subscribe("world/population", 1000, &MetricsRos::onPopulation, this, fast);
  behind_ = readHealthThresholds(pnh_, "behind");
  health_ = std::make_unique<HealthReporter>(
      nh_, pnh_, "metrics", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { fillHealth(s); },
      /*timer=*/true);
}

void MetricsRos::fillHealth(diagnostic_updater::DiagnosticStatusWrapper& s) {
  // Ticks whose world/performance or swarm/status has not all arrived: a metrics node falling behind.
  const FollowedRun* run = follower_->run();
  const double behind = static_cast<double>(follower_->waiting());
  const unsigned char level = behind_.level(behind);
  if (!run)
    s.summary(level, "waiting for a run (world/performance)");
  else
    s.summaryf(level, "run %u: %lu ticks, %lu samples%s, %.0f ticks behind", run->number,
               static_cast<unsigned long>(run->ticks_seen), static_cast<unsigned long>(samples_published_),
               run->finished ? " (finished)" : "", behind);
  s.add("run", run ? std::to_string(run->number) : std::string());
  s.add("ticks seen", run ? run->ticks_seen : 0);
  s.add("samples published", samples_published_);
  s.add("samples behind [ticks]", behind);
  s.add("library runs", library_.size());
  s.add("missing references", reported_missing_);
  s.add("diag_behind_warn [ticks]", behind_.warn);
  s.add("diag_behind_error [ticks]", behind_.error);
}

void MetricsRos::scanLibrary() {
  if (library_dir_.empty()) return;
  const RunBagCache::Scan scan = bags_.scan(library_dir_);
  std::vector<std::string> problems = scan.problems;
  for (const RunRecord* r : scan.runs)
    if (const AddResult added = library_.add(*r); !added.problem.empty()) problems.push_back(added.problem);
  for (const std::string& p : problems)
    if (reported_library_.insert(p).second) ROS_WARN("metrics: library: %s", p.c_str());
  ROS_DEBUG("metrics: library %s: %zu runs", library_dir_.c_str(), library_.size());
}

bool MetricsRos::fromFollowedWorld(const std::string& sender, const ros::Subscriber& sub, const char* topic) {
  if (world_.empty() || sender == world_ || sub.getNumPublishers() <= 1) {
    world_ = sender;
    return true;
  }
  if (refusal_log_.due())
    ROS_ERROR("metrics: ignored %s from %s: following the world %s (one world per graph)", topic,
              sender.c_str(), world_.c_str());
  return false;
}

void MetricsRos::onRunEnd(const ros::MessageEvent<const RunEnd>& event) {
  if (!fromFollowedWorld(event.getPublisherName(), end_sub_, "world/run_end")) return;
  follower_->end(runEndOf(*event.getMessage()));
}

void MetricsRos::onRunInfo(const ros::MessageEvent<const RunInfo>& event) {
  if (!fromFollowedWorld(event.getPublisherName(), info_sub_, "world/run_info")) return;
  const RunInfo& info = *event.getMessage();
  follower_->describe(info.run, describeRun(info, interval_));
}

void MetricsRos::onThrottle(const Throttle::ConstPtr& msg) { follower_->condition(conditionSampleOf(*msg)); }

void MetricsRos::onNoise(const NoiseChange::ConstPtr& msg) { noiseChanged(*follower_, *msg); }

void MetricsRos::onPopulation(const Population::ConstPtr& msg) { followPopulation(*follower_, *msg); }

void MetricsRos::onPerformance(const ros::MessageEvent<const Performance>& event) {
  if (!fromFollowedWorld(event.getPublisherName(), performance_sub_, "world/performance")) return;
  const Performance& p = *event.getMessage();
  follower_->performance(performanceOf(p), p.header.stamp.toNSec());
}

void MetricsRos::onStatus(const ros::MessageEvent<const SwarmStatus>& event) {
  follower_->status(statusOf(*event.getMessage(), event.getPublisherName()));
}

void MetricsRos::described(const FollowedRun&) {
  reported_missing_.clear();
  scanLibrary();  // the references may have been recorded since the last run
}

void MetricsRos::warn(const std::string& what) { ROS_WARN("metrics: %s", what.c_str()); }
void MetricsRos::error(const std::string& what) { ROS_ERROR("metrics: %s", what.c_str()); }

void MetricsRos::sample(const FollowedRun& run, const IntervalSample& s, uint64_t stamp_ns) {
  ros::Time stamp;
  stamp.fromNSec(stamp_ns);
  ++samples_published_;
  IntervalPerformance msg;
  msg.header.stamp = stamp;
  msg.run = run.number;
  msg.swarm_size = run.swarm_size;
  msg.tick_end = s.tick_end;
  msg.interval_ticks = s.interval_ticks;
  msg.P = s.cumulative;
  msg.p = s.delivered;
  msg.n_ca = s.mean_in_avoidance;
  msg.s = s.speed;
  msg.final = s.final;
  interval_pub_.publish(msg);
  if (csv_.is_open()) {
    writeSampleRow(csv_, run.number, run.swarm_size, s);
    csv_.flush();
  }
  if (run.description) publishMetrics(run, s, stamp);
  if (!s.final) return;
  ROS_INFO("metrics: run %u done: %u robots, %lu ticks, %lu blocks delivered, mean interference %.2f robots",
           run.number, run.swarm_size, static_cast<unsigned long>(run.ticks_seen),
           static_cast<unsigned long>(s.cumulative),
           run.ticks_seen ? static_cast<double>(run.in_avoidance_total) / run.ticks_seen : 0.0);
  if (exit_on_final_ && finish_) finish_(0);
}

void MetricsRos::publishMetrics(const FollowedRun& run, const IntervalSample& s, const ros::Time& stamp) {
  SampleContext c;
  c.stamp = stamp;
  c.run = run.number;
  c.key = run.description->key;
  c.tick_end = s.tick_end;
  c.final = s.final;
  c.definitions = definitions_;
  const RunSeries& series = run.builder->series();
  const RunEvaluation ev = evaluateRun(library_, c.key, series, s.final, definitions_, band_);
  scalability_pub_.publish(toMsg(c, ev.scalability, ev.scalability_status));
  self_organization_pub_.publish(toMsg(c, ev.self_organization, ev.self_organization_status));
  reactivity_pub_.publish(toMsg(c, ev.reactivity, ev.reactivity_status));
  adaptability_pub_.publish(toMsg(c, ev.adaptability, ev.adaptability_status));
  // Only runs with noise or population dynamics have robustness; their references are the same identity
  // without those words (docs/robustness-measures.md).
  const RobustnessEvaluation robust =
      evaluateRobustness(library_, c.key, series, run.description->seed, s.final, definitions_, band_);
  if (robust.saa_applies || robust.pd_applies) robustness_pub_.publish(toMsg(c, robust));

  std::string missing;
  for (const Evaluated* e : {&ev.scalability_status, &ev.self_organization_status, &ev.reactivity_status})
    if (!e->valid && missing.empty() && (e != &ev.reactivity_status || !c.key.environment.ideal()))
      missing = e->status;  // an ideal run without R and A is expected, not a problem
  if (!missing.empty() && reported_missing_.empty()) {
    reported_missing_ = missing;
    ROS_WARN("metrics: run %u (%s): %s", c.run, c.key.label().c_str(), missing.c_str());
  }
  if (!s.final) return;
  ROS_INFO("metrics: run %u (%s): e = %.4g%s, Z = %.4g%s, R = %.4g%s, A = %.4g%s", c.run,
           c.key.label().c_str(), ev.scalability.e.value, ev.scalability_status.valid ? "" : " (n/a)",
           ev.self_organization.z_sum.value, ev.self_organization_status.valid ? "" : " (n/a)",
           ev.reactivity.distance.value, ev.reactivity_status.valid ? "" : " (n/a)",
           ev.adaptability.distance.value, ev.adaptability_status.valid ? "" : " (n/a)");
  if (robust.saa_applies)
    ROS_INFO("metrics: run %u: SAA robustness d = %.4g, normalised %.4g%s", c.run, robust.saa.distance.value,
             robust.saa.normalized.value,
             robust.saa_status.valid ? "" : (" (n/a: " + robust.saa_status.status + ")").c_str());
  if (robust.pd_applies)
    ROS_INFO("metrics: run %u: PD robustness theta = %.4g, normalised %.4g%s", c.run, robust.pd.theta.value,
             robust.pd.normalized.value,
             robust.pd_status.valid ? "" : (" (n/a: " + robust.pd_status.status + ")").c_str());
  if (!run.changed_live.empty()) return;  // not kept in the library
  RunRecord done;
  done.key = c.key;
  done.seed = run.description->seed;
  done.source = "live run " + std::to_string(c.run);
  done.series = series;
  done.out_of_swarm =
      run.out_of_swarm.totals(c.key.setup.ticks);  // whole only if every tick's record came in time
  if (const AddResult added = library_.add(done); !added.problem.empty())
    ROS_WARN("metrics: library: %s", added.problem.c_str());
}

bool MetricsRos::onCompute(Compute::Request& req, Compute::Response& res) {
  const std::string dir = req.directory.empty() ? library_dir_ : req.directory;
  const std::string out = req.output.empty() ? dir : req.output;
  try {
    if (dir.empty()) throw std::runtime_error("no directory given and no ~library set");
    const Definitions defs = req.definitions.empty() ? definitions_ : parseDefinitions(req.definitions);
    const uint32_t interval = req.sample_interval != 0 ? req.sample_interval : interval_;
    if (interval > 100000000) throw std::runtime_error("sample_interval must be in [1, 100000000] ticks");
    RunBagCache other(interval);
    RunBagCache& bags = interval == interval_ ? bags_ : other;
    const ComputedTables computed = computeTables(bags, dir, out, defs, band_);
    res.problems = computed.problems;
    res.scalability = computed.tables.scalability;
    res.self_organization = computed.tables.self_organization;
    res.flexibility = computed.tables.flexibility;
    res.robustness = computed.tables.robustness;
    res.tables = computed.files;
    res.success = computed.error.empty();
    res.message = res.success ? computed.summary : computed.error;
  } catch (const std::exception& e) {
    res.success = false;
    res.message = e.what();
  }
  ROS_INFO("metrics: compute %s: %s", dir.c_str(), res.message.c_str());
  for (const std::string& p : res.problems) ROS_WARN("metrics: compute: %s", p.c_str());
  return true;
}

}  // namespace swarm_forage
