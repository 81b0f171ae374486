#pragma once
// The environmental condition of one tick as the world applies it (docs/design-model.md, Environmental
// condition): the value V and what it acts on.
#include <cstdint>

namespace swarm_forage {

/// What V acts on (the condition's `target`).
enum class ConditionTarget : uint8_t {
  kCarrySpeed,        // robots carrying a block move at (1 - V) x commanded (the paper's condition)
  kSpeed,             // every robot moves at (1 - V) x commanded
  kManipulationTime,  // a pick-up or drop takes max(0, V) x kMaxManipulationSeconds longer; speeds untouched
};

/// With target manipulation_time, V = 1 makes every pick-up and drop take this much longer [s].
constexpr double kMaxManipulationSeconds = 10.0;

/// V of one tick and its target. A number alone is V on the carrying speed (what World::step took before
/// targets existed).
struct Throttling {
  Throttling(double v = 0.0, ConditionTarget t = ConditionTarget::kCarrySpeed)  // NOLINT: implicit on purpose
      : value(v), target(t) {}
  double value;
  ConditionTarget target;
};

}  // namespace swarm_forage
