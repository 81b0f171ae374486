#include "swarm_forage/ros/headless_run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/ros/known_params.hpp"

namespace swarm_forage {

/// A line on stderr every `every` ticks: how far the run is and how fast it goes.
class HeadlessRun::Progress : public RunSink {
 public:
  Progress(uint64_t every, uint64_t ticks) : every_(every), ticks_(ticks) {}
  bool isRecord() const override { return false; }
  bool wantsSnapshot() const override { return false; }
  void begin(const RunDescription&, const std::string&) override { started_ = Clock::now(); }
  void snapshot(uint64_t, const SensorData&, const BlockField&) override {}
  void caches(uint64_t, const StaticCache&) override {}
  void fixed(const RunDescription&) override {}
  void stepped(const std::vector<StatusRecord>&, const PerformanceRecord& p) override {
    if (!every_ || (p.tick + 1) % every_ != 0) return;
    const double wall = std::chrono::duration<double>(Clock::now() - started_).count();
    std::fprintf(stderr, "run_experiment: tick %llu of %llu, %llu blocks, %.3g robot-ticks/s\n",
                 static_cast<unsigned long long>(p.tick + 1), static_cast<unsigned long long>(ticks_),
                 static_cast<unsigned long long>(p.cumulative),
                 wall > 0 ? (p.tick + 1) * p.swarm_size / wall : 0.0);
  }
  void end(RunEndRecord&) override {}

 private:
  using Clock = std::chrono::steady_clock;
  uint64_t every_, ticks_;
  Clock::time_point started_;
};

std::vector<std::string> HeadlessRun::parameterNames() {
  std::vector<std::string> names = worldModelParams();
  for (const auto& group :
       {std::vector<std::string>{"controller", "ticks", "record_every", "bag", "bag_dir", "outcome",
                                 "progress", "compression", "threads", "label", "overwrite"},
        conditionParams(), controllerSections()})
    names.insert(names.end(), group.begin(), group.end());
  return names;
}

std::string HeadlessRun::usage() {
  const WordParams defaults({});
  HeadlessRun probe(defaults);  // every reader tells `defaults` what it accepts
  std::string sections;
  for (const std::string& kind : controllerNames()) sections += (sections.empty() ? "" : ", ") + kind + "/*";
  std::ostringstream out;
  out << "usage: run_experiment NAME:=VALUE ... [check:=true] | --help | --version | --controllers |\n"
         "       --conditions ...\n"
         "One run without a ROS master (world, controllers and environment in lockstep), recorded like a\n"
         "node-graph run when bag:= or bag_dir:= is given. check:=true validates every parameter (the world\n"
         "places its robots) and runs nothing. Without arguments: this text, exit code 2. --version prints\n"
         "the model version and code a record would carry (YAML: model_version, code). --controllers lists\n"
         "the controller kinds (YAML: name, display_name, colour, constants, line_of_sight, "
         "static_cache).\n--conditions [ticks:=T] [ticks_per_second:=F] checks conditions read from stdin, "
         "one a\n"
         "line (tab-separated waveform:=... beta:=... words), and prints \"ok<TAB>tag\" or "
         "\"error<TAB>why\".\n\n"
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
  paramController(p);  // a plugin's constants are parameters once it is loaded
  const std::vector<std::string> valid = parameterNames();
  for (const std::string& name : p.unknown(valid))
    throw ParameterError(name + " is not a run_experiment parameter; valid: " + joinNames(valid));
  const RunDescription run = readRunDescription(p);
  const RunOutputs outputs = RunOutputs::read(p, "");
  RunSchedule schedule;
  schedule.record_every = outputs.record_every;
  const auto every = static_cast<uint64_t>(paramInRange(p, "progress", 0, 0, 2000000000));
  const Condition condition = readCondition(p, run.ticks, run.world.ticks_per_second);
  const ControllerConfigs configs = readControllerConfigs(p);
  const auto pool = std::make_shared<WorkerPool>(readThreads(p));
  const auto ns_per_tick = static_cast<uint64_t>(std::llround(1e9 / run.world.ticks_per_second));
  controllers_ = std::make_unique<InProcessControllers>(configs, pool);
  environment_ = std::make_unique<InProcessEnvironment>(condition, run.world.ticks_per_second);
  bag_ = std::make_unique<BagSink>(outputs, ns_per_tick, [](const std::string& t) { return "/" + t; });
  outcome_ = std::make_unique<OutcomeFile>(outputs.outcome);
  progress_ = std::make_unique<Progress>(every, run.ticks);
  run_ = std::make_unique<Run>(run, schedule, pool, *controllers_, *environment_,  // validates the world
                               std::vector<RunSink*>{bag_.get(), progress_.get(), outcome_.get()},
                               outputs.label);
}

HeadlessRun::~HeadlessRun() = default;

std::string HeadlessRun::run(const std::atomic<bool>& stop) {
  const RunEndRecord end = run_->execute([&stop](uint64_t tick) {
    return stop ? "interrupted (signal) at tick " + std::to_string(tick) : std::string();
  });
  bag_written_ = end.bag;
  return end.complete ? "" : end.reason;
}

}  // namespace swarm_forage
