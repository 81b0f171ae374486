#include "swarm_forage/ros/metrics_ros.hpp"

#include <swarm_forage/IntervalPerformance.h>

#include <filesystem>

#include "swarm_forage/ros/known_params.hpp"
#include "swarm_forage/ros/metrics_messages.hpp"
#include "swarm_forage/ros/params.hpp"
#include "swarm_forage/ros/run_messages.hpp"
#include "swarm_forage/ros/run_tables.hpp"

namespace swarm_forage {

namespace {
constexpr std::size_t kMaxPendingTicks = 5000;  // beyond this a tick is declared incomplete

}  // namespace

MetricsRos::MetricsRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish)
    : nh_(nh), pnh_(pnh), finish_(std::move(finish)) {
  refuseUnknownParams(pnh_, parameterNames(), "metrics_node");
  interval_ = static_cast<uint32_t>(paramInRange(pnh_, "sample_interval", 1000, 1, 100000000));
  exit_on_final_ = param<bool>(pnh_, "exit_on_final", false);
  definitions_ = parseDefinitions(paramOneOf(pnh_, "definitions", "paper", {"paper", "authors_code_2019"}));
  const int band = paramInRange(pnh_, "dtw_band", 0, 0, 100000000);
  if (band > 0) band_ = static_cast<std::size_t>(band);
  library_dir_ = param<std::string>(pnh_, "library", "");
  bags_ = RunBagCache(interval_);
  if (!library_dir_.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(library_dir_, ec);
    if (ec || !std::filesystem::is_directory(library_dir_))
      throw ParameterError("~library '" + library_dir_ + "' is not a directory that can be created or read");
    scanLibrary();
  }
  const std::string csv = param<std::string>(pnh_, "csv", "");
  if (!csv.empty()) {
    csv_.open(csv);
    if (!csv_) throw ParameterError("~csv '" + csv + "' cannot be written");
    csv_ << "run,swarm_size,tick_end,interval_ticks,P,p,n_ca,s,final\n" << std::flush;
  }
  // Replays publish as fast as asked: queues deep enough that no tick is dropped.
  const auto fast = ros::TransportHints().tcpNoDelay();
  interval_pub_ = nh_.advertise<IntervalPerformance>("metrics/performance", 100);
  scalability_pub_ = nh_.advertise<ScalabilityMetric>("metrics/scalability", 100);
  self_organization_pub_ = nh_.advertise<SelfOrganizationMetric>("metrics/self_organization", 100);
  reactivity_pub_ = nh_.advertise<FlexibilityMetric>("metrics/reactivity", 100);
  adaptability_pub_ = nh_.advertise<FlexibilityMetric>("metrics/adaptability", 100);
  compute_srv_ = nh_.advertiseService("metrics/compute", &MetricsRos::onCompute, this);
  info_sub_ = nh_.subscribe("world/run_info", 100, &MetricsRos::onRunInfo, this, fast);
  end_sub_ = nh_.subscribe("world/run_end", 100, &MetricsRos::onRunEnd, this, fast);
  performance_sub_ = nh_.subscribe("world/performance", 100000, &MetricsRos::onPerformance, this, fast);
  status_sub_ = nh_.subscribe("swarm/status", 100000, &MetricsRos::onStatus, this, fast);
  throttle_sub_ = nh_.subscribe("environment/throttle", 1000, &MetricsRos::onThrottle, this, fast);
  behind_ = readHealthThresholds(pnh_, "behind", 100, 1000, 1e9);
  health_ = std::make_unique<HealthReporter>(
      nh_, pnh_, "metrics", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { fillHealth(s); },
      /*timer=*/true);
}

void MetricsRos::fillHealth(diagnostic_updater::DiagnosticStatusWrapper& s) {
  // Ticks whose world/performance or swarm/status has not all arrived: a metrics node falling behind.
  const double behind = static_cast<double>(pending_.size());
  const unsigned char level = behind_.level(behind);
  if (!run_)
    s.summary(level, "waiting for a run (world/performance)");
  else
    s.summaryf(level, "run %u: %lu ticks, %lu samples%s, %.0f ticks behind", run_->number,
               static_cast<unsigned long>(run_->ticks_seen), static_cast<unsigned long>(samples_published_),
               run_->finished ? " (finished)" : "", behind);
  s.add("run", run_ ? std::to_string(run_->number) : std::string());
  s.add("ticks seen", run_ ? run_->ticks_seen : 0);
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

bool MetricsRos::follow(uint32_t run, uint64_t tick) {
  // A newer run, or (a world restarted, a bag replayed again) any run from tick 0 once the followed one
  // has finished or been abandoned.
  const bool fresh = !run_ || run > run_->number || (run_->finished && (run != run_->number || tick == 0));
  if (!fresh) return run == run_->number;
  if (run_ && !run_->finished)
    abandonRun("run " + std::to_string(run) + " started before it reached its last tick");
  startRun(run);
  return true;
}

void MetricsRos::startRun(uint32_t run) {
  run_.emplace();
  run_->number = run;
  next_tick_.reset();
  pending_.clear();
  stale_.clear();
  reported_missing_.clear();
}

void MetricsRos::abandonRun(const std::string& why) {
  if (!run_ || run_->finished) return;
  ROS_WARN("metrics: run %u stopped at tick %lu without its final tick (%s): left out of the library",
           run_->number, static_cast<unsigned long>(next_tick_.value_or(0)), why.c_str());
  run_->finished = true;
  pending_.clear();
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
  const RunEnd::ConstPtr& msg = event.getMessage();
  if (run_ && msg->run == run_->number && !msg->complete) abandonRun(msg->reason);
}

void MetricsRos::onRunInfo(const ros::MessageEvent<const RunInfo>& event) {
  if (!fromFollowedWorld(event.getPublisherName(), info_sub_, "world/run_info")) return;
  const RunInfo::ConstPtr& msg = event.getMessage();
  infos_[msg->run] = {*msg, false};
  drain();
}

void MetricsRos::onThrottle(const Throttle::ConstPtr& msg) {
  // A waveform changed by hand (dynamic_reconfigure): its metrics still follow the V applied, but the run
  // must not become a reference.
  if (run_ && run_->info && !run_->finished && run_->changed_live.empty() &&
      !sameWaveform(*msg, run_->info->environment)) {
    run_->changed_live = reconfiguredLive(*msg);
    ROS_WARN("metrics: run %u: %s", run_->number, run_->changed_live.c_str());
  }
}

bool MetricsRos::claimInfo() {
  if (run_->info) return true;
  const auto it = infos_.find(run_->number);
  if (it == infos_.end() || it->second.second) return false;
  it->second.second = true;
  run_->info = it->second.first;
  run_->builder = std::make_unique<RunSeriesBuilder>(interval_, run_->info->swarm_size);
  scanLibrary();  // the references may have been recorded since the last run
  return true;
}

MetricsRos::Pending& MetricsRos::pending(uint64_t tick, uint32_t swarm_size) {
  auto [it, fresh] = pending_.try_emplace(tick);
  if (fresh) it->second.status.begin(swarm_size);
  return it->second;
}

void MetricsRos::onPerformance(const ros::MessageEvent<const Performance>& event) {
  if (!fromFollowedWorld(event.getPublisherName(), performance_sub_, "world/performance")) return;
  const Performance::ConstPtr& msg = event.getMessage();
  // world/performance comes once per tick from one world: tick 0 of the followed run again, or of an
  // earlier run number, while the followed run is unfinished is a world started afresh (the last one was
  // interrupted; run numbers start at 0 again). Its earlier swarm/status waited in stale_.
  if (run_ && !run_->finished && msg->tick == 0 &&
      (msg->run < run_->number || (msg->run == run_->number && next_tick_ && *next_tick_ > 0))) {
    auto early = std::move(stale_);
    abandonRun("a world started run " + std::to_string(msg->run) + " from tick 0");
    startRun(msg->run);
    next_tick_ = 0;
    for (const auto& e : early)
      if (e.getMessage()->run == msg->run) onStatus(e);
  }
  if (!follow(msg->run, msg->tick)) return;
  if (next_tick_ && msg->tick >= *next_tick_) stale_.clear();  // the followed world is alive
  if (!next_tick_) {
    next_tick_ = msg->tick;
    if (msg->tick != 0)
      ROS_WARN("metrics: joined run %u at tick %lu; intervals count from there", msg->run,
               static_cast<unsigned long>(msg->tick));
  }
  if (msg->tick < *next_tick_) return;
  run_->swarm_size = msg->swarm_size;
  pending(msg->tick, msg->swarm_size).performance = *msg;
  drain();
}

void MetricsRos::onStatus(const ros::MessageEvent<const SwarmStatus>& event) {
  const SwarmStatus& msg = *event.getMessage();
  if (!follow(msg.run, msg.tick) || (next_tick_ && msg.tick < *next_tick_)) {
    // Perhaps the first ticks of a world started afresh: kept until its world/performance tells.
    if (run_ && !run_->finished && stale_.size() < kMaxPendingTicks) stale_.push_back(event);
    return;
  }
  Pending& p = pending(msg.tick, msg.swarm_size);
  if (p.status.add(msg.first_id, msg.count, event.getPublisherName()) == RangeCoverage::Added::kNew)
    p.in_avoidance += msg.in_avoidance;
  drain();
}

void MetricsRos::drain() {
  while (run_ && next_tick_ && !pending_.empty()) {
    auto it = pending_.find(*next_tick_);
    const bool has_info = claimInfo();
    const bool complete =
        it != pending_.end() && it->second.performance && it->second.status.complete() && has_info;
    if (!complete) {
      if (pending_.size() < kMaxPendingTicks) return;
      ROS_ERROR("metrics: tick %lu never completed (%s); counting it with what arrived",
                static_cast<unsigned long>(*next_tick_),
                it == pending_.end()            ? "nothing arrived"
                : !it->second.performance       ? "no world/performance"
                : !it->second.status.complete() ? it->second.status.missing().c_str()
                                                : "no world/run_info for this run");
      if (it == pending_.end() || !it->second.performance) {
        if (it != pending_.end()) pending_.erase(it);
        ++*next_tick_;
        continue;
      }
      if (!run_->builder) run_->builder = std::make_unique<RunSeriesBuilder>(interval_, run_->swarm_size);
    }
    const Performance& perf = *it->second.performance;
    ++run_->ticks_seen;
    run_->in_avoidance_total += it->second.in_avoidance;
    const auto sample = run_->builder->add(perf.tick, perf.delivered, perf.cumulative,
                                           it->second.in_avoidance, perf.last, perf.throttle);
    const ros::Time stamp = perf.header.stamp;
    pending_.erase(it);
    ++*next_tick_;
    if (sample) publishSample(*sample, stamp);
    if (!run_ || run_->finished) return;
  }
}

void MetricsRos::publishSample(const IntervalSample& s, const ros::Time& stamp) {
  ++samples_published_;
  IntervalPerformance msg;
  msg.header.stamp = stamp;
  msg.run = run_->number;
  msg.swarm_size = run_->swarm_size;
  msg.tick_end = s.tick_end;
  msg.interval_ticks = s.interval_ticks;
  msg.P = s.cumulative;
  msg.p = s.delivered;
  msg.n_ca = s.mean_in_avoidance;
  msg.s = s.speed;
  msg.final = s.final;
  interval_pub_.publish(msg);
  if (csv_.is_open())
    csv_ << msg.run << ',' << msg.swarm_size << ',' << s.tick_end << ',' << s.interval_ticks << ','
         << s.cumulative << ',' << s.delivered << ',' << s.mean_in_avoidance << ',' << s.speed << ','
         << (s.final ? 1 : 0) << '\n'
         << std::flush;
  if (run_->info) publishMetrics(s, stamp);
  if (!s.final) return;
  run_->finished = true;
  ROS_INFO("metrics: run %u done: %u robots, %lu ticks, %lu blocks delivered, mean interference %.2f robots",
           run_->number, run_->swarm_size, static_cast<unsigned long>(run_->ticks_seen),
           static_cast<unsigned long>(s.cumulative),
           run_->ticks_seen ? static_cast<double>(run_->in_avoidance_total) / run_->ticks_seen : 0.0);
  if (exit_on_final_ && finish_) finish_(0);
}

void MetricsRos::publishMetrics(const IntervalSample& s, const ros::Time& stamp) {
  SampleContext c;
  c.stamp = stamp;
  c.run = run_->number;
  c.key = runKey(*run_->info, interval_);
  c.tick_end = s.tick_end;
  c.final = s.final;
  c.definitions = definitions_;
  const RunSeries& series = run_->builder->series();
  const RunEvaluation ev = evaluateRun(library_, c.key, series, s.final, definitions_, band_);
  scalability_pub_.publish(toMsg(c, ev.scalability, ev.scalability_status));
  self_organization_pub_.publish(toMsg(c, ev.self_organization, ev.self_organization_status));
  reactivity_pub_.publish(toMsg(c, ev.reactivity, ev.reactivity_status));
  adaptability_pub_.publish(toMsg(c, ev.adaptability, ev.adaptability_status));

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
  if (!run_->changed_live.empty()) return;  // not kept in the library
  RunRecord done;
  done.key = c.key;
  done.seed = run_->info->seed;
  done.source = "live run " + std::to_string(c.run);
  done.series = series;
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
