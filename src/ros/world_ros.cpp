#include "swarm_forage/ros/world_ros.hpp"

#include <rosgraph_msgs/Clock.h>
#include <swarm_forage/Performance.h>
#include <swarm_forage/RunEnd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/ros/convert.hpp"
#include "swarm_forage/ros/known_params.hpp"
#include "swarm_forage/ros/params.hpp"
#include "swarm_forage/ros/run_bag.hpp"
#include "swarm_forage/ros/run_messages.hpp"
#include "swarm_forage/ros/world_frames.hpp"
#include "swarm_forage/ros/world_markers.hpp"
#include "swarm_forage/ros/world_messages.hpp"

namespace swarm_forage {

namespace {
const ros::TransportHints kFast = ros::TransportHints().tcpNoDelay();

/// The words of `a` that `b` lacks: where two constants texts differ.
std::string wordsNotIn(const std::string& a, const std::string& b) {
  std::istringstream in(a);
  std::string out, word;
  while (in >> word)
    if ((" " + b + " ").find(" " + word + " ") == std::string::npos) out += (out.empty() ? "" : " ") + word;
  return out;
}

}  // namespace

WorldRos::WorldRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish)
    : nh_(nh), pnh_(pnh) {
  refuseUnknownParams(pnh_, parameterNames(), "world_node");
  config_ = readWorldConfig(NodeParams(pnh_));
  controller_ = paramOneOf(pnh_, "controller", "crw", controllerNames());
  mode_ = paramOneOf(pnh_, "mode", "lockstep", {"lockstep", "realtime"}) == "lockstep" ? Mode::kLockstep
                                                                                       : Mode::kRealtime;
  ticks_ = static_cast<uint64_t>(paramInRange(pnh_, "ticks", 50000, 1, 2000000000));
  real_time_factor_ = paramInRange(pnh_, "real_time_factor", 1.0, kMinRealTimeFactor, kMaxRealTimeFactor);
  step_timeout_ = paramInRange(pnh_, "step_timeout", 5.0, 0.01, 3600.0);
  startup_timeout_ = paramInRange(pnh_, "startup_timeout", 30.0, 0.1, 3600.0);
  publish_every_ = paramInRange(pnh_, "publish_every", 25, 1, 1000000);
  record_every_ = paramInRange(pnh_, "record_every", 250, 1, 1000000);
  markers_rate_ = paramInRange(pnh_, "markers_rate", 5.0, 0.0, 100.0);
  frames_ = std::make_unique<WorldFrames>(pnh_);
  wait_for_subscribers_ = paramInRange(pnh_, "wait_for_subscribers", 0, 0, 1000);
  use_environment_ = param<bool>(pnh_, "use_environment", true);
  exit_when_done_ = param<bool>(pnh_, "exit_when_done", false);
  bag_path_ = param<std::string>(pnh_, "bag", "");
  bag_dir_ = param<std::string>(pnh_, "bag_dir", "");
  if (!bag_path_.empty() && !bag_dir_.empty())
    throw ParameterError("~bag and ~bag_dir are both set: give a bag's path, or a folder to name bags in");
  overwrite_ = param<bool>(pnh_, "overwrite", false);
  existing_ = bag_dir_.empty() ? explicitBagPolicy("bag", bag_path_, overwrite_) : ExistingBag::kNumber;
  label_ = param<std::string>(pnh_, "label", "");
  compression_ = paramOneOf(pnh_, "compression", "none", RunRecorder::compressions());
  outcome_path_ = param<std::string>(pnh_, "outcome", "");
  if (!outcome_path_.empty() && !std::ofstream(outcome_path_, std::ios::app))
    throw ParameterError("~outcome '" + outcome_path_ + "' cannot be appended to (a writable file path)");
  ns_per_tick_ = static_cast<uint64_t>(std::llround(1e9 / config_.ticks_per_second));
  // Validates the arena, the swarm size and (for gp_dpo) the cache.
  world_ = std::make_unique<World>(configuredFor(config_, controller_));
  pool_ = std::make_shared<WorkerPool>(readThreads(NodeParams(pnh_)));
  world_->setPool(pool_);

  nh_.setCallbackQueue(&queue_);
  clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  sensors_pub_ = nh_.advertise<SensorBatch>("world/sensors", 4);
  performance_pub_ = nh_.advertise<Performance>("world/performance", 1000);
  robots_pub_ = nh_.advertise<RobotStateArray>("world/robots", 4);
  blocks_pub_ = nh_.advertise<BlockArray>("world/blocks", 4);
  caches_pub_ = nh_.advertise<CacheArray>("world/caches", 4, /*latch=*/true);
  nest_pub_ = nh_.advertise<Nest>("world/nest", 1, /*latch=*/true);
  info_pub_ = nh_.advertise<RunInfo>("world/run_info", 1, /*latch=*/true);
  provenance_pub_ = nh_.advertise<Provenance>("world/provenance", 1, /*latch=*/true);
  provenance_pub_.publish(provenanceMsg(label_));
  end_pub_ = nh_.advertise<RunEnd>("world/run_end", 1, /*latch=*/true);
  markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("world/markers", 1);
  commands_sub_ = nh_.subscribe("swarm/commands", 64, &WorldRos::onCommands, this, kFast);
  status_sub_ = nh_.subscribe("swarm/status", 64, &WorldRos::onStatus, this, kFast);
  throttle_sub_ = nh_.subscribe("environment/throttle", 64, &WorldRos::onThrottle, this, kFast);
  reset_srv_ = nh_.advertiseService("world/reset", &WorldRos::onReset, this);
  info_srv_ = nh_.advertiseService("world/info", &WorldRos::onInfo, this);
  guard_ = std::make_unique<WorldGuard>(nh_, pnh_.getNamespace());
  health_ = std::make_unique<WorldHealth>(
      nh_, pnh_, mode_ == Mode::kLockstep, [this] { return missingReplies(); },
      [this](diagnostic_updater::DiagnosticStatusWrapper& s) {
        s.add("bag", recorder_.state());
        s.add("markers built", markers_built_);  // none while world/markers has no subscriber
        s.add("markers build and publish [ms]", 1e3 * markers_seconds_);  // the last one
      });
  WorldPaceConfig pace;
  pace.real_time_factor = real_time_factor_;
  pace_ = std::make_unique<Reconfigurable<WorldPaceConfig>>(
      pnh_, pace, [this](const WorldPaceConfig& c) { return repace(c); });
  thread_ = std::thread([this, finish] {
    int code = 1;
    try {
      code = run();
    } catch (const std::exception& e) {
      ROS_FATAL("world: %s", e.what());
    }
    recorder_.close(false);  // whatever happened, the bag so far is readable
    if (finish) finish(code);
  });
}

WorldRos::~WorldRos() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

int WorldRos::run() {
  if (const std::string other = guard_->check(/*now=*/true); !other.empty())
    return guard_->refuse(other, startup_timeout_, stop_);  // before publishing anything: no run_end
  if (const std::string missing = waitForPeers(); !missing.empty()) {
    if (stop_ || !ros::ok()) return 0;
    ROS_FATAL("world: %s", missing.c_str());
    endRun("start-up: " + missing);
    return 1;
  }
  for (;;) {
    beginRun();
    std::string stopped;
    try {
      stopped = stepRun();
    } catch (const std::exception& e) {
      endRun(std::string("error at tick ") + std::to_string(world_->tick()) + ": " + e.what());
      throw;
    }
    const bool whole = endRun(stopped);
    if (!stopped.empty()) {
      if (pending_reset_) continue;
      return stop_ || !ros::ok() ? 0 : 1;  // a shutdown from outside is not this node's failure
    }
    if (exit_when_done_) return whole ? 0 : 1;
    while (!pending_reset_ && !stop_ && ros::ok()) {
      health_->poll();
      queue_.callAvailable(ros::WallDuration(0.1));
    }
    if (!pending_reset_) return 0;
  }
}

RunInfo WorldRos::runInfo() const {
  return runInfoMsg(world_->config(), controller_, run_, ticks_,
                    mode_ == Mode::kLockstep ? "lockstep" : "realtime",
                    constants_.empty() ? std::string() : constants_.begin()->second, throttle_, ns_per_tick_);
}

std::string WorldRos::publishRunInfo() {
  // Sent once the first tick's replies are in, so that it can name the environment and the constants.
  for (const auto& [node, constants] : constants_)
    if (constants != constants_.begin()->second)
      return "tick 0: the controller nodes run different constants (" + constants_.begin()->first + ": " +
             wordsNotIn(constants_.begin()->second, constants) + "; " + node + ": " +
             wordsNotIn(constants, constants_.begin()->second) + "): one run needs one set";
  info_ = runInfo();
  info_pub_.publish(info_);
  recorder_.write(info_pub_.getTopic(), info_.header.stamp, info_);
  info_sent_ = true;
  if (!bag_dir_.empty()) recorder_.rename(bag_dir_ + "/" + runBagName(info_));
  return "";
}

void WorldRos::beginRun() {
  if (pending_reset_) {
    if (!pending_reset_->controller.empty()) controller_ = pending_reset_->controller;
    WorldConfig next = configuredFor(world_->config(), controller_);
    next.seed = pending_reset_->seed;
    next.n_robots = pending_reset_->n_robots;
    world_ = std::make_unique<World>(next);
    world_->setPool(pool_);
    ++run_;
    pending_reset_.reset();
  }
  const WorldConfig& c = world_->config();
  commands_.resize(c.n_robots);
  const Nest nest = nestMsg(c.arena);
  nest_pub_.publish(nest);
  info_sent_ = false;
  recorded_throttle_.reset();
  constants_.clear();
  range_error_.clear();
  heard_.clear();
  info_ = runInfo();  // what is known before tick 0, should the run end before it
  frames_->beginRun(*world_);
  if (!bag_path_.empty() || !bag_dir_.empty()) {
    // ~bag_dir: named once tick 0 has told the run's identity (publishRunInfo); until then by what is known.
    std::string path =
        !bag_dir_.empty()
            ? bag_dir_ + "/" +
                  fileSafe(controller_ + "_" + c.arena.name + "_n" + std::to_string(c.n_robots) + "_seed" +
                           std::to_string(c.seed) + "_run" + std::to_string(run_)) +
                  ".bag"
            : bag_path_;
    if (run_ > 0 && bag_dir_.empty()) {
      path = path.substr(0, path.rfind(".bag")) + "_run" + std::to_string(run_) + ".bag";
      explicitBagPolicy("bag", path, overwrite_);  // a later run's name is checked as the first one's was
    }
    recorder_.open(path, compression_, existing_);
    recorder_.write(nest_pub_.getTopic(), tickTime(0, ns_per_tick_), nest);
    recorder_.write(provenance_pub_.getTopic(), tickTime(0, ns_per_tick_), provenanceMsg(label_));
    ROS_INFO("world: recording run %u to %s%s", run_, path.c_str(),
             bag_dir_.empty() ? "" : " (renamed after the run's identity once tick 0 is in)");
  }
  ROS_INFO("world: run %u: %s, %u robots in %s, seed %u, %lu ticks, %s", run_, controller_.c_str(),
           c.n_robots, c.arena.name.c_str(), c.seed, static_cast<unsigned long>(ticks_),
           mode_ == Mode::kLockstep ? "lockstep" : "realtime");
  run_started_ = ros::WallTime::now();
  health_->beginRun(run_, ticks_, c.n_robots);
}

std::string WorldRos::stepRun() {
  ros::WallTime next;
  while (world_->tick() < ticks_) {
    const uint64_t tick = world_->tick();
    if (pending_reset_) return "world/reset at tick " + std::to_string(tick);
    if (stop_ || !ros::ok()) return shutdownReason(tick);
    publishTick(tick);
    // Realtime runs too wait for tick 0's replies: they tell the run's constants and who serves whom.
    std::string failed;
    if (mode_ == Mode::kLockstep || tick == 0) {
      failed = awaitReplies(tick);
      next = ros::WallTime::now();
    } else {
      next += ros::WallDuration(1.0 / (config_.ticks_per_second * real_time_factor_));  // live pace
      failed = waitRealtime(tick, next);
    }
    if (failed.empty()) failed = guard_->check();
    if (failed.empty() && !info_sent_) failed = publishRunInfo();
    if (!failed.empty()) return failed;
    TaskCounts tasks;
    for (const auto& st : status_) {
      tasks.harvesters += st.harvesters;
      tasks.collectors += st.collectors;
    }
    const StepResult result = world_->step(commands_, throttle_ ? throttle_->value : 0.0, tasks);
    publishAfterStep(tick, result);
    health_->stepped();
    health_->poll();
  }
  return "";
}

bool WorldRos::endRun(const std::string& stopped) {
  RunEnd end = runEndMsg(run_, world_ ? world_->tick() : 0, ticks_, stopped, info_.identity, ns_per_tick_);
  recorder_.write(end_pub_.getTopic(), end.header.stamp, end);
  end.bag = recorder_.close(end.complete);
  if (!recorder_.error().empty()) {  // recorded, but not under its name: not a finished record
    end.reason = (end.complete ? "" : end.reason + "; ") + recorder_.error();
    end.complete = false;
  }
  end_pub_.publish(end);
  const std::string where = end.bag.empty() ? "" : "; recorded in " + end.bag;
  const double wall = (ros::WallTime::now() - run_started_).toSec();
  using Status = diagnostic_msgs::DiagnosticStatus;
  health_->phase(end.complete ? "run " + std::to_string(run_) + " finished" + where
                              : "run " + std::to_string(run_) + " stopped at tick " +
                                    std::to_string(end.ticks_done) + " (" + end.reason + ")" + where,
                 end.complete ? Status::OK : Status::ERROR);
  health_->reportNow();
  if (end.complete)
    ROS_INFO("world: run %u finished: %lu ticks, %lu blocks delivered; %.2f s wall, %.3g robot-ticks/s%s",
             run_, static_cast<unsigned long>(end.ticks_done),
             static_cast<unsigned long>(world_->delivered()), wall,
             wall > 0 ? static_cast<double>(end.ticks_done) * world_->config().n_robots / wall : 0.0,
             where.c_str());
  else
    ROS_ERROR("world: run %u stopped at tick %lu of %lu (%s)%s", run_,
              static_cast<unsigned long>(end.ticks_done), static_cast<unsigned long>(end.ticks),
              end.reason.c_str(), where.c_str());
  if (!outcome_path_.empty() && !appendOutcome(outcome_path_, end))
    ROS_ERROR("world: cannot append to ~outcome %s", outcome_path_.c_str());
  return end.complete;
}

void WorldRos::publishTick(uint64_t tick) {
  world_->sense(sensors_);
  publishSensors(tick);
  publishSnapshots(tick, tick % publish_every_ == 0, tick % record_every_ == 0);
  if (world_->config().cache.enabled) publishCachesOnChange(tick);
  publishMarkers(tick);
  frames_->publish(*world_, sensors_, tickTime(tick, ns_per_tick_));
  awaited_tick_ = tick;
  health_->tickStarted(tick);
  commands_seen_.begin(world_->config().n_robots);
  status_seen_.begin(world_->config().n_robots);
  status_.clear();
  if (mode_ == Mode::kLockstep && use_environment_) throttle_.reset();
}

void WorldRos::publishMarkers(uint64_t tick) {
  if (markers_rate_ <= 0 || markers_pub_.getNumSubscribers() == 0) return;  // nothing is built for nobody
  const ros::WallTime now = ros::WallTime::now();
  if (!markers_last_.isZero() && (now - markers_last_).toSec() < 1.0 / markers_rate_) return;
  markers_last_ = now;
  paintMarkers(*world_, sensors_, commands_, tickTime(tick, ns_per_tick_), markers_);
  markers_pub_.publish(markers_);
  ++markers_built_;
  markers_seconds_ = (ros::WallTime::now() - now).toSec();
}

void WorldRos::publishSensors(uint64_t tick) {
  const ros::Time stamp = tickTime(tick, ns_per_tick_);
  rosgraph_msgs::Clock clock;
  clock.clock = stamp;
  clock_pub_.publish(clock);
  auto msg = boost::make_shared<SensorBatch>();
  msg->header.stamp = stamp;
  msg->tick = tick;
  msg->run = run_;
  msg->seed = world_->config().seed;
  msg->controller = controller_;
  msg->swarm_size = world_->config().n_robots;
  const Rect nest = world_->config().arena.nest();
  msg->nest_x = static_cast<float>((nest.min_x + nest.max_x) / 2);
  msg->nest_y = static_cast<float>((nest.min_y + nest.max_y) / 2);
  msg->los_cell = static_cast<float>(world_->config().sight.cell);
  msg->los_radius = static_cast<uint32_t>(world_->config().sight.radius);
  toMsg(sensors_, *msg);
  sensors_pub_.publish(msg);
}

void WorldRos::publishAfterStep(uint64_t tick, const StepResult& result) {
  const ros::Time stamp = tickTime(tick, ns_per_tick_);
  const Performance perf = performanceMsg(*world_, result, tick, run_, throttle_ ? throttle_->value : 0.0,
                                          tick + 1 == ticks_, stamp);
  performance_pub_.publish(perf);
  if (recorder_.isOpen()) {
    if (throttle_ && recordThrottle(*throttle_, recorded_throttle_))
      recorder_.write(throttle_sub_.getTopic(), stamp, *throttle_);
    std::sort(status_.begin(), status_.end(),
              [](const SwarmStatus& a, const SwarmStatus& b) { return a.first_id < b.first_id; });
    for (const auto& s : status_) recorder_.write(status_sub_.getTopic(), stamp, s);
    recorder_.write(performance_pub_.getTopic(), stamp, perf);
  }
}

void WorldRos::publishCachesOnChange(uint64_t tick) {
  const auto msg = cacheChange(world_->cache(), tick, tickTime(tick, ns_per_tick_), cache_state_);
  if (!msg) return;
  caches_pub_.publish(*msg);
  recorder_.write(caches_pub_.getTopic(), msg->header.stamp, *msg);
}

void WorldRos::publishSnapshots(uint64_t tick, bool publish, bool record) {
  if (!(record && recorder_.isOpen()) &&
      !(publish && (robots_pub_.getNumSubscribers() > 0 || blocks_pub_.getNumSubscribers() > 0)))
    return;
  const ros::Time stamp = tickTime(tick, ns_per_tick_);
  const RobotStateArray robots = robotsMsg(sensors_, tick, stamp);
  const BlockArray blocks = blocksMsg(world_->blocks(), sensors_, tick, stamp);
  if (publish) {
    robots_pub_.publish(robots);
    blocks_pub_.publish(blocks);
  }
  if (record && recorder_.isOpen()) {
    recorder_.write(robots_pub_.getTopic(), stamp, robots);
    recorder_.write(blocks_pub_.getTopic(), stamp, blocks);
  }
}

}  // namespace swarm_forage
