#pragma once
// GP-DPO foraging (docs/design-model.md, Controllers): DPO robots that choose tasks from a two-level task
// graph — generalist (block -> nest), or its subtasks harvester (block -> static cache, kCacheDrop) and
// collector (cache -> nest, kCachePickup then CRW transport) — from per-robot execution-time estimates.
//
// Interpretations where the design is silent:
// - Estimates are seeded per robot from CounterRng(seed, kController, id, kSeedTick) in the order
//   generalist, harvester, collector; a task's measured execution time is the ticks from its allocation
//   to its finish (nest drop done, or cache drop done for a harvester) or abort; aborts update the
//   estimate too (as FORDYCA/RCPPSW). After each finish or abort: estimate EMA, then P_partition is
//   recomputed, then the next task is allocated in the same tick.
// - Allocation draws: u1 for the partition (subtask iff P_partition > u1); then, for a subtask, u2:
//   with no previous subtask harvester iff u2 < 0.5, else switch from the previous subtask to the other
//   iff subtaskSwitchProbability(E_prev, E_other) > u2. The very first allocation is at the first step.
// - Abort is drawn once per tick (after the transitions; never in the tick a task starts) while at the
//   interface: a harvester in transport (carrying toward the cache), a collector in explore, vector or
//   leave_nest (heading to the cache). p uses the current task's estimate. An aborting harvester drops
//   its block where it is (kDrop: a free block, state abort_drop) and then starts its new task.
// - Caches are remembered like blocks (same pheromone model, from los_cache_*) and chosen by the same
//   utility without the exclusion radius. A cache is used as soon as the ground shows kCacheGround
//   (the cache is large; its centre need not be in sight). A harvester with no known cache explores
//   (CRW wander) while carrying; a collector with none explores. A remembered cache is forgotten when
//   its centre is in sight and it is not reported, when the robot reaches its centre without standing
//   in a cache, or (the nearest one) when a cache pick-up reports kBlockVanished.
// - A collector's nest drop is CRW's (nest wander, then kDrop); the world counts it. Every robot leaves
//   the nest like DPO, by wandering (FORDYCA's leaving-nest state), and only then acquires its next goal.
// - time_varying selects the varying_* seed ranges and partition reactivity instead of the ideal_* ones;
//   in YAML `estimates: ideal | time_varying`. The DPO behaviour constants are `dpo` (dpo.yaml).
#include <cstdint>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/dpo.hpp"

namespace swarm_forage {

/// GP-DPO's states: DPO's (same values, so that DPO's transitions serve them), then the cache pick-up and
/// drop and the drop of an aborted harvester's block.
enum class GpDpoState : uint8_t {
  kExplore,
  kVector,
  kPickup,
  kTransport,
  kNestWander,
  kDrop,
  kLeaveNest,
  kCachePickup,
  kCacheDrop,
  kAbortDrop,
  kCount
};
const char* gpDpoStateName(GpDpoState s);
constexpr uint32_t stateBit(GpDpoState s) { return 1u << static_cast<int>(s); }

enum class GpTask : uint8_t { kGeneralist = 0, kHarvester = 1, kCollector = 2, kNone = 3 };
const char* gpTaskName(GpTask t);

/// Execution-time estimates [ticks], indexed by task.
struct TaskEstimates {
  double e[3] = {0, 0, 0};
  double& operator[](GpTask t) { return e[static_cast<int>(t)]; }
  double operator[](GpTask t) const { return e[static_cast<int>(t)]; }
};

struct GpDpoConfig {
  DpoConfig dpo;              // DPO behaviour of every task (dpo.yaml)
  bool time_varying = false;  // which estimate seeds and partition reactivity: ideal or time-varying
  double ideal_generalist_min = 20000, ideal_generalist_max = 40000;  // ticks
  double ideal_subtask_min = 10000, ideal_subtask_max = 20000;        // ticks, harvester and collector
  double ideal_partition_reactivity = 6.0;                            // r
  double varying_generalist_min = 2000, varying_generalist_max = 4000;
  double varying_subtask_min = 1000, varying_subtask_max = 2000;
  double varying_partition_reactivity = 4.0;
  double ema_weight = 0.8;          // est <- (1 - w) est + w measured
  double partition_initial = 0.5;   // P_partition before the first finish or abort
  double subtask_reactivity = 8.0;  // switch P = logistic(k (E_from / E_to - offset)) ...
  double subtask_offset = 1.25;
  double abort_reactivity = 8.0;  // abort p = 1 / (1 + exp(k |t_exec / E - offset|))
  double abort_offset = 3.0;

  double generalistMin() const { return time_varying ? varying_generalist_min : ideal_generalist_min; }
  double generalistMax() const { return time_varying ? varying_generalist_max : ideal_generalist_max; }
  double subtaskMin() const { return time_varying ? varying_subtask_min : ideal_subtask_min; }
  double subtaskMax() const { return time_varying ? varying_subtask_max : ideal_subtask_max; }
  double partitionReactivity() const {
    return time_varying ? varying_partition_reactivity : ideal_partition_reactivity;
  }
  void validate() const;  // throws ParameterError naming the field and its range
};

/// GP-DPO's task-allocation constants under their YAML names (config/controllers/gp_dpo.yaml).
void visitGpDpoParameters(GpDpoConfig& c, ConstantVisitor& v);

class GpDpoBatch : public DpoBatch {
 public:
  GpDpoBatch(const GpDpoConfig& config, uint32_t seed, uint32_t first_id, uint32_t count);
  std::string name() const override { return "gp_dpo"; }
  void step(uint64_t tick, const SensorData& sensors, CommandData& commands,
            ControllerStatus& status) override;

  bool checkpointable() const override;

  /// Hides DpoBatch::state: a GP-DPO robot can be in states DPO lacks.
  GpDpoState state(uint32_t local) const { return static_cast<GpDpoState>(state_[local]); }
  GpTask task(uint32_t local) const { return static_cast<GpTask>(task_[local]); }
  GpTask lastSubtask(uint32_t local) const { return static_cast<GpTask>(last_subtask_[local]); }
  uint64_t taskStart(uint32_t local) const { return task_start_[local]; }
  const TaskEstimates& estimates(uint32_t local) const { return est_[local]; }
  double partition(uint32_t local) const { return partition_[local]; }  // current P_partition
  const ObjectMemory& caches() const { return caches_; }

  /// Test hooks: give robot `local` a task started at `tick`, or set its estimates.
  void assignTask(uint32_t local, GpTask task, uint64_t tick);
  void setEstimates(uint32_t local, const TaskEstimates& estimates) { est_[local] = estimates; }

  static constexpr uint64_t kSeedTick = ~0ULL;  // counter used for the seed draws

 private:
  void enter(uint32_t local, GpDpoState next) { enterState(local, static_cast<uint8_t>(next)); }
  void restart(uint32_t local) override;
  void persistRobot(StateArchive& a, uint32_t local) override;
  /// Robot `local`'s initial task estimates (drawn once per robot id).
  void seedEstimates(uint32_t local);
  void observeCaches(uint32_t local, uint32_t i, const SensorData& s) {  // observeBlocks() for caches
    uint32_t b = 0, e = 0;
    lineOfSightSlice(s.los_cache_offset, i, b, e);
    if (caches_.size(local) != 0 || b != e) updateCaches(local, i, s, b, e);
  }
  void updateCaches(uint32_t local, uint32_t i, const SensorData& s, uint32_t b, uint32_t e);
  const Remembered* selectCache(uint32_t local, uint32_t i, const SensorData& s) const;
  void allocate(uint32_t local, uint64_t tick, CounterRng& rng);
  /// Finish or abort: estimate update, P_partition, next task.
  void endTask(uint32_t local, uint64_t tick, CounterRng& rng);
  void acquireCache(uint32_t local, uint32_t i, const SensorData& s);
  void transition(uint32_t local, uint32_t i, uint64_t tick, const SensorData& s, CounterRng& rng);
  /// At the interface between subtasks (where a task may be aborted): a harvester in transport, a
  /// collector in explore, vector or leave nest. A look-up: tasks and states are mixed (a switch
  /// mispredicts).
  bool atInterface(uint32_t local) const { return (kInterface[task_[local]] >> state_[local]) & 1u; }
  static constexpr uint32_t kInterface[] = {
      // by task: its states at the interface
      0, stateBit(GpDpoState::kTransport),
      stateBit(GpDpoState::kExplore) | stateBit(GpDpoState::kVector) | stateBit(GpDpoState::kLeaveNest), 0};
  /// GP-DPO's drives of robots [first, end) and their tasks (out.task, task_counts_).
  void chooseDrives(uint32_t first, uint32_t end, uint64_t tick, const SensorData& s,
                    CommandData& out) override;

  GpDpoConfig gp_;
  std::vector<uint8_t> task_, last_subtask_;
  std::vector<uint64_t> task_start_;
  std::vector<TaskEstimates> est_;
  std::vector<double> partition_;
  ObjectMemory caches_;
  TaskCounts task_counts_;  // this tick's, summed strip by strip
};

}  // namespace swarm_forage
