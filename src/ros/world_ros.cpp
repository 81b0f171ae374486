#include "swarm_forage/ros/world_ros.hpp"

#include <rosgraph_msgs/Clock.h>
#include <swarm_forage/Performance.h>

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/controller_factory.hpp"
#include "swarm_forage/ros/convert.hpp"
#include "swarm_forage/ros/params.hpp"
#include "swarm_forage/ros/world_messages.hpp"

namespace swarm_forage {

namespace {
const ros::TransportHints kFast = ros::TransportHints().tcpNoDelay();
}  // namespace

WorldRos::WorldRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish)
    : nh_(nh), pnh_(pnh) {
  config_.arena = loadArena(param<std::string>(pnh_, "arena", "32x16"));
  config_.n_robots = static_cast<uint32_t>(paramInRange(pnh_, "n_robots", 64, 1, 10000000));
  config_.seed = static_cast<uint32_t>(paramInRange(pnh_, "seed", 0, 0, 2147483647));
  config_.ticks_per_second = paramInRange(pnh_, "ticks_per_second", 5.0, 0.001, 1000.0);
  controller_ = paramOneOf(pnh_, "controller", "crw", controllerNames());
  mode_ = paramOneOf(pnh_, "mode", "lockstep", {"lockstep", "realtime"}) == "lockstep" ? Mode::kLockstep
                                                                                       : Mode::kRealtime;
  ticks_ = static_cast<uint64_t>(paramInRange(pnh_, "ticks", 50000, 1, 2000000000));
  real_time_factor_ = paramInRange(pnh_, "real_time_factor", 1.0, 0.001, 1000.0);
  step_timeout_ = paramInRange(pnh_, "step_timeout", 5.0, 0.01, 3600.0);
  startup_timeout_ = paramInRange(pnh_, "startup_timeout", 30.0, 0.1, 3600.0);
  publish_every_ = paramInRange(pnh_, "publish_every", 25, 1, 1000000);
  record_every_ = paramInRange(pnh_, "record_every", 250, 1, 1000000);
  wait_for_subscribers_ = paramInRange(pnh_, "wait_for_subscribers", 0, 0, 1000);
  use_environment_ = param<bool>(pnh_, "use_environment", true);
  exit_when_done_ = param<bool>(pnh_, "exit_when_done", false);
  bag_path_ = param<std::string>(pnh_, "bag", "");
  config_.cache.size_fraction =
      paramInRange(pnh_, "cache/size_fraction", config_.cache.size_fraction, 0.001, 1.0);
  config_.cache.block_fraction =
      paramInRange(pnh_, "cache/block_fraction", config_.cache.block_fraction, 0.001, 1.0);
  config_.cache.min_blocks = static_cast<uint32_t>(paramInRange(pnh_, "cache/min_blocks", 2, 1, 1000));
  config_.cache.recreation_rate =
      paramInRange(pnh_, "cache/recreation_rate", config_.cache.recreation_rate, 0.0, 100.0);
  config_.sight.cell = paramInRange(pnh_, "los_cell", config_.sight.cell, 0.01, 10.0);
  config_.sight.radius = paramInRange(pnh_, "los_radius", config_.sight.radius, 0, 100);
  ns_per_tick_ = static_cast<uint64_t>(std::llround(1e9 / config_.ticks_per_second));
  // Validates the arena, the swarm size and (for gp_dpo) the cache.
  world_ = std::make_unique<World>(configuredFor(config_, controller_));

  nh_.setCallbackQueue(&queue_);
  clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  sensors_pub_ = nh_.advertise<SensorBatch>("world/sensors", 4);
  performance_pub_ = nh_.advertise<Performance>("world/performance", 1000);
  robots_pub_ = nh_.advertise<RobotStateArray>("world/robots", 4);
  blocks_pub_ = nh_.advertise<BlockArray>("world/blocks", 4);
  caches_pub_ = nh_.advertise<CacheArray>("world/caches", 4, /*latch=*/true);
  nest_pub_ = nh_.advertise<Nest>("world/nest", 1, /*latch=*/true);
  info_pub_ = nh_.advertise<RunInfo>("world/run_info", 1, /*latch=*/true);
  commands_sub_ = nh_.subscribe("swarm/commands", 64, &WorldRos::onCommands, this, kFast);
  status_sub_ = nh_.subscribe("swarm/status", 64, &WorldRos::onStatus, this, kFast);
  throttle_sub_ = nh_.subscribe("environment/throttle", 64, &WorldRos::onThrottle, this, kFast);
  reset_srv_ = nh_.advertiseService("world/reset", &WorldRos::onReset, this);
  info_srv_ = nh_.advertiseService("world/info", &WorldRos::onInfo, this);
  thread_ = std::thread([this, finish] {
    int code = 0;
    try {
      run();
    } catch (const std::exception& e) {
      ROS_FATAL("world: %s", e.what());
      code = 1;
    }
    recorder_.close();  // whatever happened, the bag so far is readable
    if (finish) finish(code);
  });
}

WorldRos::~WorldRos() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void WorldRos::run() {
  if (!waitForPeers()) throw std::runtime_error("start-up failed (see above)");
  for (;;) {
    beginRun();
    const bool finished = stepRun();
    recorder_.close();
    if (!finished) {
      if (stop_ || !ros::ok()) return;  // shut down from outside
      throw std::runtime_error("run " + std::to_string(run_) + " stopped at tick " +
                               std::to_string(world_->tick()) + "; the bag holds every tick before it");
    }
    const double wall = (ros::WallTime::now() - run_started_).toSec();
    ROS_INFO("world: run %u finished: %lu ticks, %lu blocks delivered; %.2f s wall, %.3g robot-ticks/s", run_,
             static_cast<unsigned long>(world_->tick()), static_cast<unsigned long>(world_->delivered()),
             wall, wall > 0 ? static_cast<double>(world_->tick()) * world_->config().n_robots / wall : 0.0);
    if (exit_when_done_) return;
    while (!pending_reset_ && !stop_ && ros::ok()) queue_.callAvailable(ros::WallDuration(0.1));
    if (!pending_reset_) return;
  }
}

bool WorldRos::waitForPeers() {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(startup_timeout_);
  std::string waiting;
  while (!stop_ && ros::ok()) {
    waiting.clear();
    if (sensors_pub_.getNumSubscribers() == 0) waiting += " a controller_node subscribed to world/sensors;";
    if (commands_sub_.getNumPublishers() == 0) waiting += " a publisher of swarm/commands;";
    if (use_environment_ && throttle_sub_.getNumPublishers() == 0)
      waiting += " an environment_node publishing environment/throttle (or ~use_environment false);";
    if (static_cast<int>(performance_pub_.getNumSubscribers()) < wait_for_subscribers_)
      waiting += " " + std::to_string(wait_for_subscribers_) +
                 " subscribers of world/performance (~wait_for_subscribers);";
    if (waiting.empty()) {
      ros::WallDuration(0.5).sleep();  // lets the other nodes' links to each other settle too
      return true;
    }
    if (ros::WallTime::now() > deadline) {
      ROS_FATAL("world: still waiting after ~startup_timeout %.1f s for:%s", startup_timeout_,
                waiting.c_str());
      return false;
    }
    queue_.callAvailable(ros::WallDuration(0.05));
  }
  return false;
}

RunInfo WorldRos::runInfo() const {
  RunInfo info;
  const WorldConfig& c = world_->config();
  info.header.stamp = tickTime(0, ns_per_tick_);
  info.run = run_;
  info.controller = controller_;
  info.arena = c.arena.name;
  info.arena_x = static_cast<float>(c.arena.width);
  info.arena_y = static_cast<float>(c.arena.height);
  info.swarm_size = c.n_robots;
  info.seed = c.seed;
  info.ticks = ticks_;
  info.ticks_per_second = c.ticks_per_second;
  info.n_blocks = c.arena.n_blocks;
  if (throttle_) info.environment = *throttle_;
  if (info.environment.waveform.empty()) info.environment.waveform = "null";
  return info;
}

void WorldRos::publishRunInfo() {
  // Sent once the first tick's replies are in, so that it can name the environment of the run.
  const RunInfo info = runInfo();
  info_pub_.publish(info);
  recorder_.write(info_pub_.getTopic(), info.header.stamp, info);
  info_sent_ = true;
}

void WorldRos::beginRun() {
  if (pending_reset_) {
    if (!pending_reset_->controller.empty()) controller_ = pending_reset_->controller;
    WorldConfig next = configuredFor(world_->config(), controller_);
    next.seed = pending_reset_->seed;
    next.n_robots = pending_reset_->n_robots;
    world_ = std::make_unique<World>(next);
    ++run_;
    pending_reset_.reset();
  }
  const WorldConfig& c = world_->config();
  commands_.resize(c.n_robots);
  const Nest nest = nestMsg(c.arena);
  nest_pub_.publish(nest);
  info_sent_ = false;
  if (!tf_static_) tf_static_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
  const Rect n = c.arena.nest();
  tf_static_->sendTransform(
      {staticFrame("arena", 0, 0), staticFrame("nest", (n.min_x + n.max_x) / 2, (n.min_y + n.max_y) / 2)});
  if (!bag_path_.empty()) {
    std::string path = bag_path_;
    if (run_ > 0) path = path.substr(0, path.rfind(".bag")) + "_run" + std::to_string(run_) + ".bag";
    recorder_.open(path);
    recorder_.write(nest_pub_.getTopic(), tickTime(0, ns_per_tick_), nest);
    ROS_INFO("world: recording run %u to %s", run_, path.c_str());
  }
  ROS_INFO("world: run %u: %s, %u robots in %s, seed %u, %lu ticks, %s", run_, controller_.c_str(),
           c.n_robots, c.arena.name.c_str(), c.seed, static_cast<unsigned long>(ticks_),
           mode_ == Mode::kLockstep ? "lockstep" : "realtime");
  run_started_ = ros::WallTime::now();
}

bool WorldRos::stepRun() {
  const ros::WallDuration period(1.0 / (config_.ticks_per_second * real_time_factor_));
  ros::WallTime next = ros::WallTime::now();
  while (world_->tick() < ticks_) {
    if (stop_ || !ros::ok() || pending_reset_) return pending_reset_.has_value();
    const uint64_t tick = world_->tick();
    publishTick(tick);
    if (mode_ == Mode::kLockstep) {
      if (!awaitReplies(tick)) return false;
    } else {
      next += period;
      waitRealtime(next);
    }
    if (!info_sent_) publishRunInfo();
    TaskCounts tasks;
    for (const auto& st : status_) {
      tasks.harvesters += st.harvesters;
      tasks.collectors += st.collectors;
    }
    const StepResult result = world_->step(commands_, throttle_ ? throttle_->value : 0.0, tasks);
    publishAfterStep(tick, result);
  }
  return true;
}

void WorldRos::publishTick(uint64_t tick) {
  world_->sense(sensors_);
  publishSensors(tick);
  publishSnapshots(tick, tick % publish_every_ == 0, tick % record_every_ == 0);
  if (world_->config().cache.enabled) publishCachesOnChange(tick);
  awaited_tick_ = tick;
  commands_seen_.begin(world_->config().n_robots);
  status_seen_.begin(world_->config().n_robots);
  status_.clear();
  if (mode_ == Mode::kLockstep && use_environment_) throttle_.reset();
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

bool WorldRos::awaitReplies(uint64_t tick) {
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime resend = start + ros::WallDuration(1.0);
  for (;;) {
    if (commands_seen_.complete() && status_seen_.complete() && (throttle_ || !use_environment_)) return true;
    queue_.callAvailable(ros::WallDuration(0.01));
    if (stop_ || !ros::ok()) return false;
    const ros::WallTime now = ros::WallTime::now();
    if (now - start > ros::WallDuration(step_timeout_)) {
      std::string missing = commands_seen_.missing();
      if (!status_seen_.complete()) missing += (missing.empty() ? "" : "; ") + status_seen_.missing();
      if (use_environment_ && !throttle_)
        missing += (missing.empty() ? "" : "; ") + std::string("environment/throttle") +
                   (throttle_sender_.empty() ? " (no environment node has ever answered)"
                                             : " from " + throttle_sender_);
      ROS_ERROR("world: tick %lu: no reply within ~step_timeout %.2f s: %s", static_cast<unsigned long>(tick),
                step_timeout_, missing.c_str());
      return false;
    }
    if (now > resend) {  // a node that connected late missed the first send: offer the tick again
      publishSensors(tick);
      resend = now + ros::WallDuration(1.0);
    }
  }
}

void WorldRos::waitRealtime(ros::WallTime deadline) {
  while (ros::WallTime::now() < deadline && !stop_ && ros::ok())
    queue_.callAvailable(
        std::max(ros::WallDuration(0.0), std::min(deadline - ros::WallTime::now(), ros::WallDuration(0.01))));
}

void WorldRos::publishAfterStep(uint64_t tick, const StepResult& result) {
  const ros::Time stamp = tickTime(tick, ns_per_tick_);
  Performance perf;
  perf.header.stamp = stamp;
  perf.tick = tick;
  perf.run = run_;
  perf.swarm_size = world_->config().n_robots;
  perf.delivered = result.delivered;
  perf.cumulative = world_->delivered();
  perf.carrying = world_->carrying();
  perf.throttle = throttle_ ? throttle_->value : 0.0;
  perf.last = tick + 1 == ticks_;
  performance_pub_.publish(perf);
  if (recorder_.isOpen()) {
    if (throttle_) recorder_.write(throttle_sub_.getTopic(), stamp, *throttle_);
    std::sort(status_.begin(), status_.end(),
              [](const SwarmStatus& a, const SwarmStatus& b) { return a.first_id < b.first_id; });
    for (const auto& s : status_) recorder_.write(status_sub_.getTopic(), stamp, s);
    recorder_.write(performance_pub_.getTopic(), stamp, perf);
  }
}

void WorldRos::publishCachesOnChange(uint64_t tick) {
  const StaticCache& cache = world_->cache();
  const auto state = std::make_pair(cache.exists(), cache.size());
  if (tick != 0 && state == cache_state_) return;
  cache_state_ = state;
  CacheArray msg = cacheMsg(cache);
  msg.header.stamp = tickTime(tick, ns_per_tick_);
  msg.header.frame_id = "map";
  msg.tick = tick;
  caches_pub_.publish(msg);
  recorder_.write(caches_pub_.getTopic(), msg.header.stamp, msg);
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

void WorldRos::onCommands(const ros::MessageEvent<const CommandBatch>& event) {
  const CommandBatch& msg = *event.getMessage();
  const bool current = mode_ == Mode::kRealtime || msg.tick == awaited_tick_;
  if (msg.run != run_ || !current) return;  // a late answer to an earlier tick or run
  const std::size_t n = msg.left.size();
  if (msg.right.size() != n || msg.request.size() != n) {
    ROS_ERROR_THROTTLE(5, "world: malformed swarm/commands from %s (array sizes differ)",
                       event.getPublisherName().c_str());
    return;
  }
  if (mode_ == Mode::kRealtime) commands_seen_.begin(world_->config().n_robots);
  if (commands_seen_.add(msg.first_id, static_cast<uint32_t>(n), event.getPublisherName()))
    mergeInto(msg, commands_);
}

void WorldRos::onStatus(const ros::MessageEvent<const SwarmStatus>& event) {
  const SwarmStatus& msg = *event.getMessage();
  if (msg.run != run_ || (mode_ == Mode::kLockstep && msg.tick != awaited_tick_)) return;
  if (mode_ == Mode::kRealtime) status_seen_.begin(world_->config().n_robots);
  if (status_seen_.add(msg.first_id, msg.count, event.getPublisherName())) status_.push_back(msg);
}

void WorldRos::onThrottle(const ros::MessageEvent<const Throttle>& event) {
  const Throttle& msg = *event.getMessage();
  if (mode_ == Mode::kLockstep && msg.tick != awaited_tick_) return;
  throttle_ = msg;
  throttle_sender_ = event.getPublisherName();
}

bool WorldRos::onReset(Reset::Request& req, Reset::Response& res) {
  try {
    const auto& names = controllerNames();
    if (!req.controller.empty() && std::find(names.begin(), names.end(), req.controller) == names.end())
      throw ParameterError("controller '" + req.controller + "' is unknown; valid: crw, dpo, gp_dpo");
    WorldConfig next = configuredFor(world_->config(), req.controller.empty() ? controller_ : req.controller);
    if (req.seed != 0) next.seed = req.seed;
    if (req.swarm_size != 0) next.n_robots = req.swarm_size;
    next.validate();
    pending_reset_ = PendingReset{next.seed, next.n_robots, req.controller};
    res.success = true;
    res.run = run_ + 1;
    res.message = "run " + std::to_string(res.run) + " starts with seed " + std::to_string(next.seed) +
                  " and " + std::to_string(next.n_robots) + " robots";
  } catch (const ParameterError& e) {
    res.success = false;
    res.run = run_;
    res.message = e.what();
  }
  return true;
}

bool WorldRos::onInfo(Info::Request&, Info::Response& res) {
  res.run = runInfo();
  res.nest = nestMsg(world_->config().arena);
  const Rect s = world_->config().arena.source();
  res.source_x = {static_cast<float>(s.min_x), static_cast<float>(s.max_x)};
  res.source_y = {static_cast<float>(s.min_y), static_cast<float>(s.max_y)};
  res.caches = cacheMsg(world_->cache());
  return true;
}

}  // namespace swarm_forage
