#include "swarm_forage/ros/world_node/world_ros.hpp"

#include <rosgraph_msgs/Clock.h>
#include <swarm_forage/Performance.h>
#include <swarm_forage/Population.h>
#include <swarm_forage/RunEnd.h>
#include <swarm_forage/SensorBatch.h>

#include <cmath>

#include "swarm_forage/ros/messages/run_messages.hpp"
#include "swarm_forage/ros/messages/world_messages.hpp"
#include "swarm_forage/ros/params/known_params.hpp"
#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

WorldRos::WorldRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish)
    : nh_(nh), pnh_(pnh) {
  refuseUnknownParams(pnh_, parameterNames(), "world_node");
  RunDescription first = readRunDescription(NodeParams(pnh_), readExternalController(NodeParams(pnh_)));
  first.mode = readParam<std::string>(pnh_, "mode");
  lockstep_ = first.mode == "lockstep";
  real_time_factor_ = readParam<double>(pnh_, "real_time_factor");
  step_timeout_ = readParam<double>(pnh_, "step_timeout");
  startup_timeout_ = readParam<double>(pnh_, "startup_timeout");
  schedule_.publish_every = static_cast<uint32_t>(readParam<int>(pnh_, "publish_every"));
  const double markers_rate = readParam<double>(pnh_, "markers_rate");
  frames_ = std::make_unique<WorldFrames>(pnh_);
  wait_for_subscribers_ = readParam<int>(pnh_, "wait_for_subscribers");
  use_environment_ = readParam<bool>(pnh_, "use_environment");
  exit_when_done_ = readParam<bool>(pnh_, "exit_when_done");
  const RunOutputs outputs = RunOutputs::read(NodeParams(pnh_), "~");
  label_ = outputs.label;
  schedule_.record_every = outputs.record_every;
  ns_per_tick_ = static_cast<uint64_t>(std::llround(1e9 / first.world.ticks_per_second));
  pool_ = std::make_shared<WorkerPool>(readThreads(NodeParams(pnh_)));
  bag_ = std::make_unique<BagSink>(outputs, ns_per_tick_,
                                   [this](const std::string& t) { return nh_.resolveName(t); });
  outcome_ = std::make_unique<OutcomeFile>(outputs.outcome);
  // Validates the arena, the swarm size and (for gp_dpo) the cache.
  newRun(first);

  nh_.setCallbackQueue(&queue_);
  clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  sensors_pub_ = nh_.advertise<SensorBatch>("world/sensors", 4);
  performance_pub_ = nh_.advertise<Performance>("world/performance", 1000);
  if (first.world.population.enabled()) population_pub_ = nh_.advertise<Population>("world/population", 1000);
  robots_pub_ = nh_.advertise<RobotStateArray>("world/robots", 4);
  blocks_pub_ = nh_.advertise<BlockArray>("world/blocks", 4);
  caches_pub_ = nh_.advertise<CacheArray>("world/caches", 4, /*latch=*/true);
  nest_pub_ = nh_.advertise<Nest>("world/nest", 1, /*latch=*/true);
  info_pub_ = nh_.advertise<RunInfo>("world/run_info", 1, /*latch=*/true);
  noise_pub_ = nh_.advertise<NoiseChange>("world/noise", 8, /*latch=*/true);
  provenance_pub_ = nh_.advertise<Provenance>("world/provenance", 1, /*latch=*/true);
  provenance_pub_.publish(provenanceMsg(label_));
  end_pub_ = nh_.advertise<RunEnd>("world/run_end", 1, /*latch=*/true);
  markers_ = std::make_unique<MarkerPublisher>(nh_, markers_rate);
  const ros::TransportHints fast = ros::TransportHints().tcpNoDelay();
  commands_sub_ = nh_.subscribe("swarm/commands", 64, &WorldRos::onCommands, this, fast);
  status_sub_ = nh_.subscribe("swarm/status", 64, &WorldRos::onStatus, this, fast);
  throttle_sub_ = nh_.subscribe("environment/throttle", 64, &WorldRos::onThrottle, this, fast);
  errors_sub_ = nh_.subscribe("swarm/errors", 8, &WorldRos::onControllerError, this);
  reset_srv_ = nh_.advertiseService("world/reset", &WorldRos::onReset, this);
  info_srv_ = nh_.advertiseService("world/info", &WorldRos::onInfo, this);
  guard_ = std::make_unique<WorldGuard>(nh_, pnh_.getNamespace());
  health_ = std::make_unique<WorldHealth>(
      nh_, pnh_, lockstep_, [this] { return missingReplies(); },
      [this](diagnostic_updater::DiagnosticStatusWrapper& s) {
        s.add("bag", bag_->state());
        s.add("markers built", markers_->built());
        s.add("markers build and publish [ms]", 1e3 * markers_->seconds());
        s.add("threads", pool_->threads());
        s.add("jobs on one thread, cores contended [%]", pool_->percentAlone());
        if (run_ && run_->world().population().enabled()) {  // population dynamics
          const PopulationEvents& e = run_->world().population().events();
          s.add("active robots", e.active);
          s.add("robots awaiting repair", e.queue);
          s.add("robots present", e.present);
        }
      });
  WorldPaceConfig pace;
  pace.real_time_factor = real_time_factor_;
  pace_ = std::make_unique<Reconfigurable<WorldPaceConfig>>(
      pnh_, pace, [this](const WorldPaceConfig& c) { return repace(c); });
  if (first.world.population.enabled()) {
    rates_now_ = first.world.population;
    PopulationRatesConfig rates;
    rates.death = first.world.population.death;
    rates.birth = first.world.population.birth;
    rates.malfunction = first.world.population.malfunction;
    rates.repair = first.world.population.repair;
    rates_ = std::make_unique<Reconfigurable<PopulationRatesConfig>>(
        ros::NodeHandle(pnh_, "population"), rates,
        [this](const PopulationRatesConfig& c) { return rerate(c); });
  }
  live_noise_ = first.world.noise;
  noise_knob_ =
      std::make_unique<Reconfigurable<NoiseConfig>>(ros::NodeHandle(pnh_, "noise"), noiseConfig(live_noise_),
                                                    [this](const NoiseConfig& c) { return renoise(c); });
  thread_ = std::thread([this, finish] {
    int code = 1;
    try {
      code = run();
    } catch (const std::exception& e) {
      ROS_FATAL("world: %s", e.what());
    }
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
    run_->end(StepOutcome::stop("start-up: " + missing));
    return 1;
  }
  for (;;) {
    if (pending_reset_) reset();
    const RunEndRecord end = run_->execute([this](uint64_t tick) {
      applyNoiseChange();
      return interrupted(tick);
    });
    if (end.ticks_done < end.ticks) {  // stopped early
      if (pending_reset_) continue;
      return stop_ || !ros::ok() ? 0 : 1;  // a shutdown from outside is not this node's failure
    }
    if (exit_when_done_) return end.complete ? 0 : 1;
    while (!pending_reset_ && !stop_ && ros::ok()) {
      health_->poll();
      queue_.callAvailable(ros::WallDuration(0.1));
    }
    if (!pending_reset_) return 0;
  }
}

void WorldRos::reset() {
  RunDescription next = run_->description();
  if (!pending_reset_->controller.empty()) next.controller = pending_reset_->controller;
  next.world.seed = pending_reset_->seed;
  next.world.n_robots = pending_reset_->n_robots;
  next.run = ++run_no_;
  {
    // A new run starts with the noise shown by the knob: in its identity, no hand change.
    const std::lock_guard<std::mutex> lock(noise_mutex_);
    next.world.noise = live_noise_;
    noise_pending_ = false;
  }
  pending_reset_.reset();
  newRun(next);
}

void WorldRos::newRun(const RunDescription& run) {
  run_.reset();  // one world at a time
  run_ = std::make_unique<Run>(run, schedule_, pool_, *this, *this,
                               std::vector<RunSink*>{bag_.get(), this, outcome_.get()}, label_);
}

StepOutcome WorldRos::interrupted(uint64_t tick) {
  {
    std::lock_guard<std::mutex> lock(rates_mutex_);
    if (pending_rates_) {
      run_->setPopulationRates(*pending_rates_);  // checked when it came in
      ROS_INFO("world: population rates changed by hand at tick %lu: %s", static_cast<unsigned long>(tick),
               pending_rates_->describe(run_->world().config().n_robots).c_str());
      pending_rates_.reset();
    }
  }
  if (pending_reset_) return StepOutcome::stop("world/reset at tick " + std::to_string(tick));
  return stop_ || !ros::ok() ? StepOutcome::stop(shutdownReason(tick)) : StepOutcome::ok();
}

std::string WorldRos::shutdownReason(uint64_t tick) const {
  return "node shut down at tick " + std::to_string(tick) +
         " (Ctrl-C, rosnode kill, or roslaunch ending as a required node exited)";
}

}  // namespace swarm_forage
