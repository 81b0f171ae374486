#pragma once
// Varied per-robot readings for the DPO and GP-DPO state-machine tests: what both fill the same way
// (threat, proximity, light, carried block and events) from a robot's tick hash `h` and window hash `w`.
#include <cstdint>

#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

inline void fillVariedReadings(SensorData& s, std::size_t i, uint64_t h, uint64_t w) {
  s.threatened[i] = (h % 5 == 0) || ((w >> 20) % 9 == 0 && h % 2 == 0);
  s.obstacle_x[i] = static_cast<float>((h >> 8) % 7) * 0.03f - 0.1f;
  s.obstacle_y[i] = static_cast<float>((h >> 16) % 5) * 0.04f - 0.08f;
  s.light_x[i] = static_cast<float>((h >> 24) % 11) * 0.5f - 2.5f;
  s.light_y[i] = static_cast<float>((h >> 32) % 13) * 0.4f - 2.4f;
  const bool carrying = (h >> 40) % 3 == 0;
  s.carried_block[i] = carrying ? static_cast<int32_t>(i) : -1;
  s.events[i] =
      (h >> 48) % 4 == 0 ? (carrying ? kPickupDone : kDropDone) : ((h >> 50) % 9 == 0 ? kBlockVanished : 0);
}

}  // namespace swarm_forage
