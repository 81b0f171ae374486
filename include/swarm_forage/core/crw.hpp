#pragma once
// CRW foraging: explore by correlated random walk, take the first block found to the nest by
// phototaxis, wander in the nest, drop, leave the nest, explore again (DESIGN section 4).
#include <cstdint>
#include <string>
#include <vector>

#include "swarm_forage/core/controller.hpp"
#include "swarm_forage/core/drive.hpp"

namespace swarm_forage {

struct CrwConfig {
  double wander_step = deg2rad(5.0);   // wander angle += U[-step, step]
  double wander_limit = deg2rad(5.0);  // |wander angle| <= limit
  double wander_force = 9.0;           // cm/s
  double wander_free_scale = 0.7;      // wander force scale when no obstacle threatens
  double avoidance_force = 8.0;
  double phototaxis_force = 8.0;
  uint32_t nest_wander_ticks = 25;  // wander in the nest before dropping
  uint32_t min_explore_ticks = 50;
  DriveConfig drive;

  void validate() const;  // throws ParameterError
};

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
  /// Wander force (robot frame) after advancing robot `local`'s wander angle.
  Vec2 wander(uint32_t local, uint64_t tick, bool threatened);

  CrwConfig config_;
  uint32_t seed_;
  uint32_t first_id_;
  std::vector<uint8_t> state_;
  std::vector<uint32_t> state_ticks_;  // ticks spent in the current state
  std::vector<float> wander_angle_;
};

}  // namespace swarm_forage
