#pragma once
// The interface every controller batch implements: one sensor batch in, one command batch out.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/sensing.hpp"

namespace swarm_forage {

/// What a controller range reports each tick (DESIGN section 2, swarm/status).
struct ControllerStatus {
  uint32_t in_avoidance = 0;
  std::vector<std::string> state_names;
  std::vector<uint32_t> state_counts;
  uint32_t generalists = 0, harvesters = 0, collectors = 0;
};

/// The controller kinds this build provides.
inline const std::vector<std::string>& controllerNames() {
  static const std::vector<std::string> names = {"crw"};
  return names;
}

class ControllerBatch {
 public:
  virtual ~ControllerBatch() = default;
  virtual std::string name() const = 0;
  /// Computes commands for robots [first_id, first_id + count) from the whole swarm's sensors.
  virtual void step(uint64_t tick, const SensorData& sensors, CommandData& commands,
                    ControllerStatus& status) = 0;
};

}  // namespace swarm_forage
