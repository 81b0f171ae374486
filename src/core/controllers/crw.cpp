#include "swarm_forage/core/controllers/crw.hpp"

#include "swarm_forage/core/util/rng.hpp"

namespace swarm_forage {

const char* crwStateName(CrwState s) {
  static const char* names[] = {"explore", "pickup", "transport", "nest_wander", "drop", "leave_nest"};
  return names[static_cast<int>(s)];
}

CrwBatch::CrwBatch(const CrwConfig& config, uint32_t seed, uint32_t first_id, uint32_t count)
    : config_(config),
      seed_(seed),
      first_id_(first_id),
      state_(count, static_cast<uint8_t>(CrwState::kExplore)),
      state_ticks_(count, 0),
      wander_angle_(count, 0.f),
      stalls_(count) {
  config_.validate();
}

void CrwBatch::step(uint64_t tick, const SensorData& s, CommandData& out, ControllerStatus& status) {
  const uint32_t n = count();
  out.first_id = first_id_;
  if (out.size() != n) out.resize(n);
  status = ControllerStatus{};
  status.state_counts.assign(static_cast<std::size_t>(CrwState::kCount), 0);
  for (int k = 0; k < static_cast<int>(CrwState::kCount); ++k)
    status.state_names.push_back(crwStateName(static_cast<CrwState>(k)));

  for (uint32_t l = 0; l < n; ++l) {
    const uint32_t i = first_id_ + l;
    const bool threat = s.threatened[i] != 0;
    const uint8_t ground = s.ground[i], events = s.events[i];
    const bool carrying = s.carried_block[i] >= 0;
    auto state = static_cast<CrwState>(state_[l]);
    // Transitions driven by what the world executed and what the robot stands on.
    switch (state) {
      case CrwState::kExplore:
        if (ground == kBlockGround && !carrying && state_ticks_[l] >= config_.min_explore_ticks)
          state = CrwState::kPickup;  // the tick count carries over, see kPickup
        break;
      case CrwState::kPickup:
        if (carrying || (events & kPickupDone)) {
          state = CrwState::kTransport;
          state_ticks_[l] = 0;
        } else if (ground != kBlockGround) {
          state = CrwState::kExplore;  // keeps its exploration time
        }
        break;
      default:
        if (deliveryTransition(state, state_ticks_[l], ground, carrying, events, config_.nest_wander_ticks))
          state_ticks_[l] = 0;
        break;
    }
    // Actions of the state the robot is now in. The wander draw is the robot's only one this tick.
    CounterRng rng(seed_, RngStream::kController, i, tick);
    WheelSpeeds w;
    uint8_t request = kNone;
    switch (state) {
      case CrwState::kPickup:
        request = kPickup;  // stopped on the block
        break;
      case CrwState::kDrop:
        request = kDrop;
        break;
      case CrwState::kTransport:
        w = motionWheels(Motion::kTransport, s, i, wander_angle_[l], rng, config_);
        break;
      case CrwState::kNestWander:
        w = motionWheels(Motion::kNestWander, s, i, wander_angle_[l], rng, config_);
        break;
      case CrwState::kLeaveNest:
        w = motionWheels(Motion::kLeaveNest, s, i, wander_angle_[l], rng, config_);
        break;
      default:
        w = motionWheels(Motion::kExplore, s, i, wander_angle_[l], rng, config_);
        break;
    }
    out.left[l] = w.left;
    out.right[l] = w.right;
    out.request[l] = request;
    state_[l] = static_cast<uint8_t>(state);
    ++state_ticks_[l];
    ++status.state_counts[state_[l]];
    status.in_avoidance += threat ? 1 : 0;
    status.stalled += stalls_.stalled(l, s.x[i], s.y[i], tick);
  }
}

}  // namespace swarm_forage
