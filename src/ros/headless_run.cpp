#include "swarm_forage/ros/headless_run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/ros/known_params.hpp"
#include "swarm_forage/ros/run_messages.hpp"
#include "swarm_forage/ros/world_messages.hpp"

namespace swarm_forage {

namespace {
// The topics of a run recorded by world_node in the root namespace.
const std::string kTopicNest = "/world/nest", kTopicProvenance = "/world/provenance",
                  kTopicInfo = "/world/run_info", kTopicEnd = "/world/run_end",
                  kTopicPerformance = "/world/performance", kTopicStatus = "/swarm/status",
                  kTopicThrottle = "/environment/throttle", kTopicRobots = "/world/robots",
                  kTopicBlocks = "/world/blocks", kTopicCaches = "/world/caches";
}  // namespace

std::vector<std::string> HeadlessRun::parameterNames() {
  std::vector<std::string> names = worldModelParams();
  for (const auto& group :
       {std::vector<std::string>{"controller", "ticks", "record_every", "bag", "bag_dir", "outcome",
                                 "progress", "compression", "threads", "label", "overwrite"},
        waveformParams(), controllerSections()})
    names.insert(names.end(), group.begin(), group.end());
  return names;
}

std::string HeadlessRun::usage() {
  const WordParams defaults({});
  HeadlessRun probe(defaults);  // every reader tells `defaults` what it accepts
  std::string sections;
  for (const std::string& kind : controllerNames()) sections += (sections.empty() ? "" : ", ") + kind + "/*";
  std::ostringstream out;
  out << "usage: run_experiment NAME:=VALUE ... [check:=true] | --help | --version | --controllers\n"
         "One run without a ROS master (world, controllers and environment in lockstep), recorded like a\n"
         "node-graph run when bag:= or bag_dir:= is given. check:=true validates every parameter (the world\n"
         "places its robots) and runs nothing. Without arguments: this text, exit code 2. --version prints\n"
         "the model version and code a record would carry (YAML: model_version, code). --controllers lists\n"
         "the controller kinds (YAML: name, display_name, colour, constants, line_of_sight, "
         "static_cache).\n\n"
         "parameters:\n"
      << usageTable(defaults.usage()) << "  (controller constants " << sections
      << ": ranges in config/controllers/*.yaml, checked too)\n\n"
         "examples:\n"
         "  run_experiment controller:=dpo n_robots:=32 ticks:=20000 seed:=3 bag:=/tmp/dpo_n32.bag\n"
         "  run_experiment arena:=64x32 n_robots:=128 waveform:=step_down beta:=0.4 bag_dir:=results/\n"
         "  run_experiment n_robots:=5000 check:=true\n\n"
         "exit codes: 0 finished (or check:=true passed, or --help); 1 stopped early or failed;\n"
         "2 a bad or unknown parameter, or no arguments\n";
  return out.str();
}

HeadlessRun::HeadlessRun(const WordParams& p) {
  const std::vector<std::string> valid = parameterNames();
  for (const std::string& name : p.unknown(valid))
    throw ParameterError(name + " is not a run_experiment parameter; valid: " + joinNames(valid));
  world_config_ = readWorldConfig(p);
  controller_ = paramOneOf(p, "controller", "crw", controllerNames());
  ticks_ = static_cast<uint64_t>(paramInRange(p, "ticks", 50000, 1, 2000000000));
  record_every_ = paramInRange(p, "record_every", 250, 1, 1000000);
  compression_ = paramOneOf(p, "compression", "none", RunRecorder::compressions());
  progress_ = static_cast<uint64_t>(paramInRange(p, "progress", 0, 0, 2000000000));
  bag_path_ = param<std::string>(p, "bag", "");
  bag_dir_ = param<std::string>(p, "bag_dir", "");
  if (!bag_path_.empty() && !bag_dir_.empty())
    throw ParameterError("bag and bag_dir are both set: give a bag's path, or a folder to name bags in");
  label_ = param<std::string>(p, "label", "");
  existing_ = bag_dir_.empty() ? explicitBagPolicy("bag", bag_path_, param<bool>(p, "overwrite", false))
                               : ExistingBag::kNumber;
  outcome_path_ = param<std::string>(p, "outcome", "");
  if (!outcome_path_.empty() && !std::ofstream(outcome_path_, std::ios::app))
    throw ParameterError("outcome '" + outcome_path_ + "' cannot be appended to (a writable file path)");
  waveform_ = readWaveform(p, static_cast<int>(ticks_), world_config_.ticks_per_second);
  configs_ = readControllerConfigs(p);
  ns_per_tick_ = static_cast<uint64_t>(std::llround(1e9 / world_config_.ticks_per_second));
  const unsigned threads = readThreads(p);
  sim_ = std::make_unique<Simulation>(world_config_, controller_, configs_, threads);  // validates the world
}

std::string HeadlessRun::run(const std::atomic<bool>& stop) {
  World& world = sim_->world();
  const WorldConfig& c = world.config();
  const bool record = !bag_path_.empty() || !bag_dir_.empty();
  if (record) {
    // Named as world_node names it: by what is known until tick 0 has told the identity.
    recorder_.open(!bag_path_.empty()
                       ? bag_path_
                       : bag_dir_ + "/" +
                             fileSafe(controller_ + "_" + c.arena.name + "_n" + std::to_string(c.n_robots) +
                                      "_seed" + std::to_string(c.seed) + "_run0") +
                             ".bag",
                   compression_, existing_);
    recorder_.write(kTopicNest, tickTime(0, ns_per_tick_), nestMsg(c.arena));
    recorder_.write(kTopicProvenance, tickTime(0, ns_per_tick_), provenanceMsg(label_));
  }
  std::string constants = describeConstants(controller_, configs_), stopped, identity;
  std::pair<bool, std::size_t> cache_state{false, 0};
  std::optional<Throttle> last_throttle;
  const auto started = std::chrono::steady_clock::now();
  for (uint64_t tick = 0; tick < ticks_; ++tick) {
    if (stop) {
      stopped = "interrupted (signal) at tick " + std::to_string(tick);
      break;
    }
    const ros::Time stamp = tickTime(tick, ns_per_tick_);
    sim_->sense();
    if (record && tick % record_every_ == 0) {
      recorder_.write(kTopicRobots, stamp, robotsMsg(sim_->sensors(), tick, stamp));
      recorder_.write(kTopicBlocks, stamp, blocksMsg(world.blocks(), sim_->sensors(), tick, stamp));
    }
    if (c.cache.enabled)
      if (const auto caches = cacheChange(world.cache(), tick, stamp, cache_state))
        recorder_.write(kTopicCaches, stamp, *caches);
    const Throttle throttle = throttleMsg(waveform_, tick, c.ticks_per_second, ns_per_tick_);
    sim_->decide();
    if (tick == 0) {
      const RunInfo info =
          runInfoMsg(c, controller_, 0, ticks_, "lockstep", constants, throttle, ns_per_tick_);
      identity = info.identity;
      recorder_.write(kTopicInfo, info.header.stamp, info);
      if (!bag_dir_.empty()) recorder_.rename(bag_dir_ + "/" + runBagName(info));
    }
    const StepResult result = sim_->advance(throttle.value);
    if (record) {
      if (recordThrottle(throttle, last_throttle)) recorder_.write(kTopicThrottle, stamp, throttle);
      recorder_.write(kTopicStatus, stamp,
                      statusMsg(sim_->status(), sim_->commands(), tick, 0, c.n_robots, controller_, stamp,
                                tick == 0 ? constants : std::string()));
      recorder_.write(kTopicPerformance, stamp,
                      performanceMsg(world, result, tick, 0, throttle.value, tick + 1 == ticks_, stamp));
    }
    if (progress_ && (tick + 1) % progress_ == 0) {
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      std::fprintf(stderr, "run_experiment: tick %llu of %llu, %llu blocks, %.3g robot-ticks/s\n",
                   static_cast<unsigned long long>(tick + 1), static_cast<unsigned long long>(ticks_),
                   static_cast<unsigned long long>(world.delivered()),
                   wall > 0 ? (tick + 1) * c.n_robots / wall : 0.0);
    }
  }
  RunEnd end = runEndMsg(0, world.tick(), ticks_, stopped, identity, ns_per_tick_);
  recorder_.write(kTopicEnd, end.header.stamp, end);
  end.bag = bag_written_ = recorder_.close(stopped.empty());
  if (!recorder_.error().empty()) {  // the run is whole, but not where it belongs: not a finished record
    stopped = recorder_.error();
    end.complete = false;
    end.reason = stopped;
  }
  if (!outcome_path_.empty() && !appendOutcome(outcome_path_, end))
    throw std::runtime_error("cannot append to outcome " + outcome_path_);
  return stopped;
}

}  // namespace swarm_forage
