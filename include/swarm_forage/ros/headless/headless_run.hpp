#pragma once
// run_experiment: one run in one process, without a ROS master: the run engine with its in-process ports
// (controller batches, the condition computed in place), recorded by the same bag sink as a run through the
// node graph (topics, messages, run identity).
#include <atomic>
#include <iosfwd>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "swarm_forage/core/run/in_process.hpp"
#include "swarm_forage/core/run/run.hpp"
#include "swarm_forage/ros/params/params.hpp"
#include "swarm_forage/ros/runs/bag_sink.hpp"

namespace swarm_forage {

/// `expect_identity` is not the run's identity: the words or the files they name changed since it was
/// planned.
struct IdentityMismatch : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class HeadlessRun {
 public:
  /// Every parameter world_node, controller_node and environment_node would read, plus `progress`
  /// (print a line every that many ticks, 0: none), `compression` (none, lz4, bz2), `label` (recorded in
  /// world/provenance) and `overwrite` (replace an existing `bag`, else refused). Throws ParameterError
  /// for a bad or unknown one, and IdentityMismatch when `expect_identity` is set and differs from the
  /// planned identity (an input file changed since a sweep planned the run).
  explicit HeadlessRun(const WordParams& params);
  ~HeadlessRun();
  /// Runs to the last tick or until `stop` is set; "" when complete, else why it stopped. The bag (if
  /// any) is closed either way: NAME.bag, or NAME_incomplete.bag for a run cut short.
  std::string run(const std::atomic<bool>& stop);
  /// Where the run was recorded ("" when not).
  const std::string& bag() const { return bag_written_; }
  /// The description tick 0 will fix (in process, the constants and the condition are known before the
  /// run starts): its identity() and runBagName() are what the run will record, what a sweep plans by.
  const RunDescription& planned() const { return planned_; }

  /// The parameter names run_experiment takes (sections end in '/').
  static std::vector<std::string> parameterNames();
  /// run_experiment's --help: every parameter of the parameter table with its default, valid values and
  /// doc, the controllers' constants as their readers tell (a run built from the defaults, never
  /// started), and examples.
  static std::string usage();

 private:
  class Progress;
  /// checkpoint_every, checkpoint, save_at, save, resume (docs/runs-and-bags.md, Checkpoints).
  void readCheckpoints(const WordParams& p, const RunOutputs& outputs, const RunDescription& run,
                       const ControllerConfigs& configs);
  std::unique_ptr<InProcessControllers> controllers_;
  std::unique_ptr<InProcessEnvironment> environment_;
  std::unique_ptr<BagSink> bag_;
  std::unique_ptr<OutcomeFile> outcome_;
  std::unique_ptr<Progress> progress_;
  std::unique_ptr<Run> run_;
  std::string bag_written_;
  RunDescription planned_;
  uint64_t every_ = 0, save_at_ = 0;
  std::string checkpoint_, save_, resume_;
};

/// run_experiment --identity: for each line of `in` (one run's name:=value words, tab-separated), the line
/// "ok<TAB>IDENTITY<TAB>BAG NAME" the run would record, or "error<TAB>why" for words it would refuse. Runs
/// that differ only in seed are validated once. Returns 0.
int printIdentities(std::istream& in, std::ostream& out);

}  // namespace swarm_forage
