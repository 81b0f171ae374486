#pragma once
// The interface every controller batch implements: one sensor batch in, one command batch out.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

/// Robots per task of the GP-DPO task graph (all zero for other controllers).
struct TaskCounts {
  uint32_t generalists = 0, harvesters = 0, collectors = 0;
};

/// What a controller range reports each tick (DESIGN section 2, swarm/status).
struct ControllerStatus {
  uint32_t in_avoidance = 0;
  uint32_t stalled =
      0;  // robots that have not moved 1 cm in the last 50 ticks: a jam shows as a rising count
  std::vector<std::string> state_names;
  std::vector<uint32_t> state_counts;
  TaskCounts tasks;
};

/// The controller kinds this build provides.
inline const std::vector<std::string>& controllerNames() {
  static const std::vector<std::string> names = {"crw", "dpo", "gp_dpo"};
  return names;
}
/// Whether the world must compute line of sight for this controller kind.
inline bool needsLineOfSight(const std::string& controller) { return controller != "crw"; }
/// Whether the world runs a static cache for this controller kind.
inline bool needsStaticCache(const std::string& controller) { return controller == "gp_dpo"; }

class ControllerBatch {
 public:
  virtual ~ControllerBatch() = default;
  virtual std::string name() const = 0;
  /// Computes commands for robots [first_id, first_id + count) from the whole swarm's sensors.
  virtual void step(uint64_t tick, const SensorData& sensors, CommandData& commands,
                    ControllerStatus& status) = 0;
};

}  // namespace swarm_forage
