#pragma once
// The run engine's bag writer: a run's records as messages in a rosbag (RunRecorder), on the topics a
// world_node publishes them on, so that a node graph and run_experiment write the same bag.
#include <functional>
#include <map>
#include <string>

#include "swarm_forage/RunInfo.h"
#include "swarm_forage/Throttle.h"
#include "swarm_forage/core/run/run_ports.hpp"
#include "swarm_forage/ros/run_params.hpp"
#include "swarm_forage/ros/run_recorder.hpp"

namespace swarm_forage {

class BagSink : public RunSink {
 public:
  /// `topic` resolves a topic name as the world publishes it ("world/nest" -> "/world/nest").
  BagSink(RunOutputs outputs, uint64_t ns_per_tick, std::function<std::string(const std::string&)> topic);
  bool isRecord() const override { return true; }
  bool wantsSnapshot() const override { return recorder_.isOpen(); }
  /// Opens the run's bag (when the outputs name one) under a temporary name; throws std::runtime_error
  /// when it cannot (ParameterError: a later run's ~bag exists).
  void begin(const RunDescription& run, const std::string& label) override;
  void snapshot(uint64_t tick, const SensorData& sensors, const BlockField& blocks) override;
  void caches(uint64_t tick, const StaticCache& cache) override;
  /// world/run_info; a bag in ~bag_dir is named by the identity from now on.
  void fixed(const RunDescription& run) override;
  void condition(uint64_t tick, const ConditionSample& c) override;
  void population(const PopulationRecord& p) override;
  /// world/noise: a hand change.
  void noiseChanged(uint64_t tick, const SaaNoise& noise) override;
  void stepped(const std::vector<StatusRecord>& status, const PerformanceRecord& performance) override;
  void end(RunEndRecord& end) override;
  /// Checkpoints: the bag so far, whole (RunRecorder::checkpoint); the run goes on appending to it.
  void save(StateArchive& a) override;
  /// Starts the run's bag (named as begin() and fixed() would) as the checkpoint's, and appends from there;
  /// a fork's gets the fork's world/run_info and environment/throttle records instead of the parent's.
  void resume(StateArchive& a, const RunDescription& run, uint64_t tick,
              const std::vector<ConditionSample>* fork) override;
  const RunOutputs& outputs() const { return outputs_; }
  /// The path the current run's bag was opened for ("" when the run is not recorded).
  const std::string& path() const { return path_; }
  /// What the bag is doing, for /diagnostics.
  std::string state() const { return recorder_.state(); }

 private:
  /// What close() does when the bag's name is taken (begin() and resume()).
  ExistingBag policy(const RunDescription& run, const std::string& path) const;
  /// Replaces in the bag `file` (a checkpoint's, at `tick`) world/run_info by `info` and the
  /// environment/throttle records, in order, by `throttles`: what a fork's fresh run recorded.
  void forkRecords(const std::string& file, const RunInfo& info, const std::vector<Throttle>& throttles,
                   uint64_t tick) const;

  RunOutputs outputs_;
  uint64_t ns_per_tick_;
  uint32_t run_ = 0;                           // the current run's number
  std::map<std::string, std::string> topics_;  // name -> as the world publishes it
  RunRecorder recorder_;
  std::string path_;
};

}  // namespace swarm_forage
