#pragma once
// The run engine's bag writer: a run's records as messages in a rosbag (RunRecorder), on the topics a
// world_node publishes them on, so that a node graph and run_experiment write the same bag.
#include <functional>
#include <map>
#include <string>

#include "swarm_forage/core/run/run_ports.hpp"
#include "swarm_forage/ros/params/run_params.hpp"
#include "swarm_forage/ros/runs/run_recorder.hpp"

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
  void identityFixed(const RunDescription& run) override;
  void condition(uint64_t tick, const ConditionSample& c) override;
  void population(const PopulationRecord& p) override;
  /// world/noise: a hand change.
  void noiseChanged(uint64_t tick, const SaaNoise& noise) override;
  void stepped(const std::vector<StatusRecord>& status, const PerformanceRecord& performance) override;
  void end(RunEndRecord& end) override;
  /// Checkpoints: the bag so far as its segments (RunRecorder::checkpoint), named by file, size and
  /// checksum, or carried whole after carrySegments(true); the run goes on in a new segment.
  void save(StateArchive& a) override;
  /// The next save() carries the segments' bytes: a fork's source (save_at:=) outlives this run's
  /// segments, which its close() joins and removes.
  void carrySegments(bool carry) { carry_ = carry; }
  /// The last save() is in the checkpoint file `file` now: a run stopped with nothing recorded since
  /// leaves its record to it (no NAME_incomplete.bag).
  void checkpointWritten(const std::string& file);
  /// A signal's flag: the end's join of segments that a checkpoint names stops when it is set.
  void setStop(const std::atomic<bool>* stop) { recorder_.setStop(stop); }
  /// The checkpoint file resume() read (it names the segments a resumed run continues in place).
  void resumedFrom(const std::string& file) { checkpoint_ = file; }
  /// Continues the run's bag (named as begin() and identityFixed() would) from the checkpoint's segments, in
  /// place; a fork copies them, with the fork's world/run_info and environment/throttle records instead of
  /// the parent's. The killed writer's leftovers are removed. CheckpointError: a segment missing or changed.
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

  RunOutputs outputs_;
  uint64_t ns_per_tick_;
  uint32_t run_ = 0;                           // the current run's number
  std::map<std::string, std::string> topics_;  // name -> as the world publishes it
  RunRecorder recorder_;
  std::string path_;
  bool carry_ = false;
  std::string checkpoint_;  // the checkpoint file that names the segments ("" when none does)
};

}  // namespace swarm_forage
