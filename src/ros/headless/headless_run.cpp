#include "swarm_forage/ros/headless/headless_run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <istream>
#include <map>
#include <ostream>
#include <sstream>

#include "swarm_forage/core/controllers/controller_constants.hpp"
#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/run/checkpoint.hpp"
#include "swarm_forage/ros/params/known_params.hpp"

namespace swarm_forage {

/// A line on stderr every `every` ticks: how far the run is and how fast it goes.
class HeadlessRun::Progress : public RunSink {
 public:
  Progress(uint64_t every, uint64_t ticks) : every_(every), ticks_(ticks) {}
  bool isRecord() const override { return false; }
  bool wantsSnapshot() const override { return false; }
  void begin(const RunDescription&, const std::string&) override { started_ = Clock::now(); }
  /// A resumed run's speed counts the ticks it stepped itself.
  void resume(StateArchive&, const RunDescription&, uint64_t tick,
              const std::vector<ConditionSample>*) override {
    started_ = Clock::now();
    first_ = tick;
  }
  void snapshot(uint64_t, const SensorData&, const BlockField&) override {}
  void caches(uint64_t, const StaticCache&) override {}
  void identityFixed(const RunDescription&) override {}
  void stepped(const std::vector<StatusRecord>&, const PerformanceRecord& p) override {
    if (!every_ || (p.tick + 1) % every_ != 0) return;
    const double wall = std::chrono::duration<double>(Clock::now() - started_).count();
    std::fprintf(stderr, "run_experiment: tick %llu of %llu, %llu blocks, %.3g robot-ticks/s\n",
                 static_cast<unsigned long long>(p.tick + 1), static_cast<unsigned long long>(ticks_),
                 static_cast<unsigned long long>(p.cumulative),
                 wall > 0 ? (p.tick + 1 - first_) * p.swarm_size / wall : 0.0);
  }
  void end(RunEndRecord&) override {}

 private:
  using Clock = std::chrono::steady_clock;
  uint64_t every_, ticks_;
  uint64_t first_ = 0;  // the first tick this process steps
  Clock::time_point started_;
};

std::vector<std::string> HeadlessRun::parameterNames() { return knownParams(kRunExperiment); }

std::string HeadlessRun::usage() {
  const WordParams defaults({});
  HeadlessRun probe(defaults);  // every reader tells `defaults` what it accepts: the constants' ranges
  std::string sections;
  for (const std::string& kind : controllerNames()) sections += (sections.empty() ? "" : ", ") + kind + "/*";
  // The table's rows, and in place of the constants' section the constants each kind declares.
  std::vector<ParamUsage> rows;
  for (const ParamUsage& row : tableUsage(kRunExperiment)) {
    if (row.name != paramSpec("<kind>/").name) {
      rows.push_back(row);
      continue;
    }
    for (const ParamUsage& read : defaults.usage())
      if (unknownNames({read.name}, controllerSections()).empty()) rows.push_back(read);
  }
  std::ostringstream out;
  out << "usage: run_experiment NAME:=VALUE ... [check:=true] | --help | --version | --controllers |\n"
         "       --conditions ...\n"
         "One run without a ROS master (world, controllers and environment in lockstep), recorded like a\n"
         "node-graph run when bag:= or bag_dir:= is given. check:=true validates every parameter (the world\n"
         "places its robots) and runs nothing. Without arguments: this text, exit code 2. --version prints\n"
         "the model version and code a record would carry (YAML: model_version, code). --controllers lists\n"
         "the controller kinds (YAML: name, display_name, colour, constants, line_of_sight, "
         "static_cache,\ncheckpointable, package, plugin, defaults).\n--conditions [ticks:=T] "
         "[ticks_per_second:=F] checks conditions read from stdin, "
         "one a\n"
         "line (tab-separated waveform:=... beta:=... words), and prints \"ok<TAB>tag\" or "
         "\"error<TAB>why\".\n\n"
         "parameters:\n"
      << usageTable(rows) << "  (controller constants " << sections
      << ": ranges in config/controllers/*.yaml, checked too)\n\n"
         "examples:\n"
         "  run_experiment controller:=dpo n_robots:=32 ticks:=20000 seed:=3 bag:=/tmp/dpo_n32.bag\n"
         "  run_experiment arena:=64x32 n_robots:=128 waveform:=step_down beta:=0.4 bag_dir:=results/\n"
         "  run_experiment n_robots:=5000 check:=true\n"
         "  run_experiment n_robots:=4096 ticks:=50000 bag:=r.bag checkpoint_every:=5000  (then, after a "
         "kill:\n"
         "    the same words and resume:=r.bag.checkpoint; docs/runs-and-bags.md, Checkpoints)\n"
         "  run_experiment ... save_at:=25000 save:=ideal.ckpt, then waveform:=step_up beta:=0.4 "
         "alpha:=5000\n"
         "    resume:=ideal.ckpt: the step_up run forked from the ideal run at alpha\n\n"
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
  const auto every = static_cast<uint64_t>(readParam<int>(p, "progress"));
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
  readCheckpoints(p, outputs, run, configs);
  planned_ = run_->description();
  planned_.controller_constants = describeConstants(planned_.controller, configs);
  planned_.condition = environment_->condition(0);
  planned_.fixed = true;
  const std::string expected = readParam<std::string>(p, "expect_identity");
  if (!expected.empty() && expected != planned_.identity())
    throw IdentityMismatch("the run's identity is " + planned_.identity() +
                           " where expect_identity:=" + expected +
                           " was planned: its words or a file they name (arena, series) changed "
                           "since the plan");
}

void HeadlessRun::readCheckpoints(const WordParams& p, const RunOutputs& outputs, const RunDescription& run,
                                  const ControllerConfigs& configs) {
  const int ticks = static_cast<int>(std::min<uint64_t>(run.ticks, 2000000000));
  every_ = static_cast<uint64_t>(readParam<int>(p, "checkpoint_every"));
  checkpoint_ = readParam<std::string>(p, "checkpoint");
  const ParamSpec& at = paramSpec("save_at");  // its range ends at this run's ticks
  p.accepts({at.name, fallbackText(at), validText(at), at.doc});
  save_at_ = static_cast<uint64_t>(paramInRange(p, "save_at", fallbackOf<int>(at), 0, ticks));
  save_ = readParam<std::string>(p, "save");
  resume_ = readParam<std::string>(p, "resume");
  if (every_ > 0 && checkpoint_.empty()) {
    if (outputs.bag.empty())
      throw ParameterError("checkpoint_every:=" + std::to_string(every_) +
                           " needs checkpoint:=FILE (or bag:=, whose path + .checkpoint is the default)");
    checkpoint_ = outputs.bag + ".checkpoint";
  }
  if (!checkpoint_.empty() && every_ == 0)
    throw ParameterError("checkpoint:=" + checkpoint_ +
                         " needs checkpoint_every:=K (K in [1, 2000000000] ticks)");
  if ((save_at_ > 0) != !save_.empty())
    throw ParameterError(save_.empty() ? "save_at:=" + std::to_string(save_at_) + " needs save:=FILE"
                                       : "save:=" + save_ + " needs save_at:=T (T in [1, " +
                                             std::to_string(ticks) + "], the tick after which it is saved)");
  if (!save_.empty() && save_ == checkpoint_)
    throw ParameterError("save:= and checkpoint:= are both " + save_ +
                         ": the periodic checkpoint must not overwrite the saved one");
  // A folder given for a file is refused by name now, not by the file system at the first checkpoint.
  for (const auto& [name, path] : {std::pair<const char*, const std::string*>{"resume", &resume_},
                                   {"checkpoint", &checkpoint_},
                                   {"save", &save_}}) {
    std::error_code ec;
    if (!path->empty() && std::filesystem::is_directory(*path, ec))
      throw ParameterError(std::string("~") + name + " '" + *path + "' is a directory; valid: " +
                           (path == &resume_ ? "a checkpoint file that checkpoint:= or save:= wrote"
                                             : "the path of a checkpoint file to write"));
  }
  if (every_ == 0 && save_.empty() && resume_.empty()) return;
  // Start-up, not at the first checkpoint: a kind that cannot be checkpointed is refused now.
  if (!makeController(run.controller, configs, run.world.seed, 0, 1)->checkpointable())
    throw ParameterError("controller '" + run.controller +
                         "' cannot be checkpointed (its batch does not implement ControllerBatch::persist): "
                         "checkpoint_every, save_at and resume need one that does");
  if (!resume_.empty()) try {
      readCheckpointFile(resume_);  // a broken file is refused before anything runs
    } catch (const CheckpointError& e) {
      throw ParameterError(std::string("resume: ") + e.what());
    }
}

HeadlessRun::~HeadlessRun() = default;

int printIdentities(std::istream& in, std::ostream& out) {
  std::map<std::vector<std::string>, std::pair<RunDescription, std::string>> seen;  // words but the seed
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> words, others;
    std::string seed;
    for (std::size_t at = 0; at <= line.size();) {
      const std::size_t tab = std::min(line.find('\t', at), line.size());
      if (tab > at) words.push_back(line.substr(at, tab - at));
      at = tab + 1;
    }
    for (const std::string& w : words) (w.rfind("seed:=", 0) == 0 ? seed : others.emplace_back()) = w;
    auto found = seen.find(others);
    // A seed is a whole number in [0, kMaxSeed] (readWorldConfig's rule); any other runs the full check.
    const bool plain_seed =
        seed.size() > 6 && seed.size() <= 16 &&
        std::all_of(seed.begin() + 6, seed.end(), [](char c) { return c >= '0' && c <= '9'; }) &&
        std::stoll(seed.substr(6)) <= kMaxSeed;
    if (found == seen.end() || !plain_seed) {
      std::pair<RunDescription, std::string> result;
      try {
        result.first = HeadlessRun(WordParams(words)).planned();
      } catch (const std::exception& e) {
        result.second = e.what();
        std::replace(result.second.begin(), result.second.end(), '\n', ' ');  // one line per run
      }
      if (!plain_seed) {
        out << (result.second.empty() ? "ok\t" + result.first.identity() + "\t" + runBagName(result.first)
                                      : "error\t" + result.second)
            << "\n";
        continue;
      }
      found = seen.emplace(others, std::move(result)).first;
    }
    if (!found->second.second.empty()) {
      out << "error\t" << found->second.second << "\n";
      continue;
    }
    RunDescription run = found->second.first;
    run.world.seed = static_cast<uint32_t>(std::stoll(seed.substr(6)));
    out << "ok\t" << run.identity() << "\t" << runBagName(run) << "\n";
  }
  out.flush();
  return 0;
}

std::string HeadlessRun::run(const std::atomic<bool>& stop) {
  if (!resume_.empty()) try {
      run_->resume(readCheckpointFile(resume_), resume_);
      bag_->resumedFrom(resume_);
    } catch (const CheckpointError& e) {
      throw ParameterError("resume: " + resume_ + ": " + e.what());
    }
  bag_->setStop(&stop);
  uint64_t written = 0;  // the tick of this process's last periodic checkpoint (0: none yet)
  const auto periodic = [&](uint64_t tick) {
    bag_->carrySegments(false);
    writeCheckpointFile(checkpoint_, run_->checkpoint());
    bag_->checkpointWritten(checkpoint_);
    written = tick;
  };
  run_->setAfterStep([&](uint64_t done) {
    // After the last tick too: a join stopped by a signal resumes from there.
    const bool due = every_ > 0 && (done % every_ == 0 || done == run_->description().ticks);
    if (done == save_at_) {
      bag_->carrySegments(true);  // a fork's source outlives this run's segments
      const std::string payload = run_->checkpoint();
      writeCheckpointFile(save_, payload);
      if (!due) return;
      writeCheckpointFile(checkpoint_, payload);
      bag_->checkpointWritten(checkpoint_);
      written = done;
    } else if (due) {
      periodic(done);
    }
  });
  const RunEndRecord end = run_->execute([&](uint64_t tick) {
    if (!stop) return StepOutcome::ok();
    // SIGTERM (a SLURM time limit) or SIGINT: the ticks since the last checkpoint are kept too.
    if (every_ > 0 && tick > 0 && tick != written) periodic(tick);
    return StepOutcome::stop("interrupted (signal) at tick " + std::to_string(tick));
  });
  bag_written_ = end.bag;
  return end.complete ? "" : end.reason;
}

}  // namespace swarm_forage
