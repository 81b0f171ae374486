#pragma once
// run_experiment: one run in one process, without a ROS master: the core world and controllers in
// lockstep, recorded to the same bag (topics, messages, run identity) as a run through the node graph.
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/core/run/simulation.hpp"
#include "swarm_forage/ros/params.hpp"
#include "swarm_forage/ros/run_recorder.hpp"

namespace swarm_forage {

class HeadlessRun {
 public:
  /// Every parameter world_node, controller_node and environment_node would read, plus `progress`
  /// (print a line every that many ticks, 0: none), `compression` (none, lz4, bz2), `label` (recorded in
  /// world/provenance) and `overwrite` (replace an existing `bag`, else refused). Throws ParameterError
  /// for a bad or unknown one.
  explicit HeadlessRun(const WordParams& params);
  /// Runs to the last tick or until `stop` is set; "" when complete, else why it stopped. The bag (if
  /// any) is closed either way: NAME.bag, or NAME_incomplete.bag for a run cut short.
  std::string run(const std::atomic<bool>& stop);
  /// Where the run was recorded ("" when not).
  const std::string& bag() const { return bag_written_; }

  /// The parameter names run_experiment takes (sections end in '/').
  static std::vector<std::string> parameterNames();
  /// run_experiment's --help: every parameter with its default and valid values, as the readers that
  /// validate them tell (a run built from the defaults, never started), and examples.
  static std::string usage();

 private:
  WorldConfig world_config_;
  ControllerConfigs configs_;
  Condition condition_;
  std::string controller_, bag_path_, bag_dir_, outcome_path_, bag_written_, compression_, label_;
  ExistingBag existing_ = ExistingBag::kRefuse;
  uint64_t ticks_ = 0, ns_per_tick_ = 0, progress_ = 0;
  int record_every_ = 250;
  std::unique_ptr<Simulation> sim_;
  RunRecorder recorder_;
};

}  // namespace swarm_forage
