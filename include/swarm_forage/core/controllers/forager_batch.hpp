#pragma once
// The bookkeeping every forager batch shares (CRW, DPO, GP-DPO): its robot range, each robot's state,
// state clock and wander angle, and the status counted while the batch steps.
#include <cstdint>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/controllers/forage_common.hpp"

namespace swarm_forage {

class ForagerBatch : public ControllerBatch {
 public:
  uint32_t firstId() const { return first_id_; }
  uint32_t count() const { return static_cast<uint32_t>(state_.size()); }

 protected:
  ForagerBatch(uint32_t seed, uint32_t first_id, uint32_t count);  // every robot in state 0

  /// Resets the command batch and the status for this range; `state_names` are indexed by state.
  void prepare(CommandData& out, ControllerStatus& status, const std::vector<std::string>& state_names) const;
  /// Population dynamics: true when robot `local` is out of the swarm (its command is zero, no request, and
  /// its state does not advance: the caller skips it). A newcomer (Event kJoined) starts afresh (restart).
  bool idle(uint32_t local, const SensorData& s, CommandData& out);
  /// Robot `local` as at tick 0: its kind's state forgotten.
  virtual void restart(uint32_t local);
  /// Writes robot `local`'s command, advances its state clock and counts it in the status.
  void finish(uint32_t local, uint64_t tick, const SensorData& s, const WheelSpeeds& w, uint8_t request,
              CommandData& out, ControllerStatus& status);

  uint32_t seed_;
  uint32_t first_id_;
  std::vector<uint8_t> state_;         // the kind's state enum
  std::vector<uint32_t> state_ticks_;  // ticks spent in the current state
  std::vector<float> wander_angle_;
  StallTracker stalls_;
};

}  // namespace swarm_forage
