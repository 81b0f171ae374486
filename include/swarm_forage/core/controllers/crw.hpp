#pragma once
// CRW foraging: explore by correlated random walk, take the first block found to the nest by
// phototaxis, wander in the nest, drop, leave the nest, explore again (DESIGN section 4).
#include <cstdint>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/controllers/forage_common.hpp"  // CrwConfig and the shared motion primitives

namespace swarm_forage {

enum class CrwState : uint8_t { kExplore, kPickup, kTransport, kNestWander, kDrop, kLeaveNest, kCount };
const char* crwStateName(CrwState s);

class CrwBatch : public ControllerBatch {
 public:
  CrwBatch(const CrwConfig& config, uint32_t seed, uint32_t first_id, uint32_t count);
  std::string name() const override { return "crw"; }
  void step(uint64_t tick, const SensorData& sensors, CommandData& commands,
            ControllerStatus& status) override;

  CrwState state(uint32_t local) const { return static_cast<CrwState>(state_[local]); }
  uint32_t firstId() const { return first_id_; }
  uint32_t count() const { return static_cast<uint32_t>(state_.size()); }

 private:
  CrwConfig config_;
  uint32_t seed_;
  uint32_t first_id_;
  std::vector<uint8_t> state_;
  std::vector<uint32_t> state_ticks_;  // ticks spent in the current state
  std::vector<float> wander_angle_;
  StallTracker stalls_;
};

}  // namespace swarm_forage
