#pragma once
// The interface every controller batch implements: one sensor batch in, one command batch out. The
// kinds that implement it register in controller_registry.hpp.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/util/state_archive.hpp"
#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

/// Robots per task of the GP-DPO task graph (all zero for other controllers).
struct TaskCounts {
  uint32_t generalists = 0, harvesters = 0, collectors = 0;
};

/// What a controller range reports each tick (swarm/status).
struct ControllerStatus {
  uint32_t in_avoidance = 0;
  uint32_t stalled =
      0;  // robots that have not moved 1 cm in the last 50 ticks: a jam shows as a rising count
  std::vector<std::string> state_names;
  std::vector<uint32_t> state_counts;
  TaskCounts tasks;
};

class ControllerBatch {
 public:
  virtual ~ControllerBatch() = default;
  virtual std::string name() const = 0;
  /// Computes commands for robots [first_id, first_id + count) from the whole swarm's sensors.
  virtual void step(uint64_t tick, const SensorData& sensors, CommandData& commands,
                    ControllerStatus& status) = 0;
  /// Checkpoints (docs/runs-and-bags.md): whether persist() saves and loads everything the batch carries from
  /// one tick to the next. A kind that does not override both cannot be checkpointed: run_experiment refuses
  /// checkpoint_every, save_at and resume for it at start-up.
  virtual bool checkpointable() const { return false; }
  /// Saves or loads (a.loading()) the state between two ticks, robot by robot in id order, so that the
  /// parts of a range split over threads read what one batch of the range wrote.
  virtual void persist(StateArchive& /*a*/) {
    throw CheckpointError("controller '" + name() +
                          "' cannot be checkpointed (its batch does not implement "
                          "ControllerBatch::persist)");
  }
};

}  // namespace swarm_forage
