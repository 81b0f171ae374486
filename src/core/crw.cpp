#include "swarm_forage/core/crw.hpp"

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/config.hpp"
#include "swarm_forage/core/rng.hpp"

namespace swarm_forage {

namespace {
void require(bool ok, const std::string& what) {
  if (!ok) throw ParameterError(what);
}
}  // namespace

void CrwConfig::validate() const {
  require(wander_step >= 0 && wander_step <= kPi, "crw wander_step must be in [0, 180] degrees");
  require(wander_limit >= 0 && wander_limit <= kPi, "crw wander_limit must be in [0, 180] degrees");
  require(wander_force > 0 && wander_force <= 100, "crw wander_force must be in (0, 100] cm/s");
  require(wander_free_scale > 0 && wander_free_scale <= 1, "crw wander_free_scale must be in (0, 1]");
  require(avoidance_force >= 0 && avoidance_force <= 100, "crw avoidance_force must be in [0, 100] cm/s");
  require(phototaxis_force > 0 && phototaxis_force <= 100, "crw phototaxis_force must be in (0, 100] cm/s");
  require(nest_wander_ticks <= 100000, "crw nest_wander_ticks must be in [0, 100000]");
  require(min_explore_ticks <= 100000, "crw min_explore_ticks must be in [0, 100000]");
  require(drive.max_speed > 0 && drive.max_speed <= 1, "max_speed must be in (0, 1] m/s");
  require(drive.soft_turn_max > 0 && drive.soft_turn_max < kPi, "soft_turn_max must be in (0, 180) degrees");
  require(drive.hard_turn_speed > 0 && drive.hard_turn_speed <= drive.max_speed,
          "hard_turn_speed must be in (0, max_speed] m/s");
}

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
      wander_angle_(count, 0.f) {
  config_.validate();
}

Vec2 CrwBatch::wander(uint32_t local, uint64_t tick, bool threatened) {
  CounterRng rng(seed_, RngStream::kController, first_id_ + local, tick);
  const double a = std::clamp(wander_angle_[local] + rng.uniform(-config_.wander_step, config_.wander_step),
                              -config_.wander_limit, config_.wander_limit);
  wander_angle_[local] = static_cast<float>(a);
  const double m = config_.wander_force * (threatened ? 1.0 : config_.wander_free_scale);
  return {m * std::cos(a), m * std::sin(a)};
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
    Vec2 avoid(0, 0);
    if (threat) {
      const Vec2 ob(s.obstacle_x[i], s.obstacle_y[i]);
      const double len = ob.norm();
      if (len > 1e-9) avoid = -ob / len * config_.avoidance_force;
    }
    auto state = static_cast<CrwState>(state_[l]);
    const auto enter = [&](CrwState next) {
      state = next;
      state_ticks_[l] = 0;
    };
    // Transitions driven by what the world executed and what the robot stands on.
    switch (state) {
      case CrwState::kExplore:
        if (ground == kBlockGround && !carrying && state_ticks_[l] >= config_.min_explore_ticks)
          state = CrwState::kPickup;  // the tick count carries over, see kPickup
        break;
      case CrwState::kPickup:
        if (carrying || (events & kPickupDone))
          enter(CrwState::kTransport);
        else if (ground != kBlockGround)
          state = CrwState::kExplore;  // keeps its exploration time
        break;
      case CrwState::kTransport:
        if (ground == kNest) enter(CrwState::kNestWander);
        break;
      case CrwState::kNestWander:
        if (ground != kNest)
          enter(CrwState::kTransport);
        else if (state_ticks_[l] >= config_.nest_wander_ticks)
          enter(CrwState::kDrop);
        break;
      case CrwState::kDrop:
        if (!carrying || (events & kDropDone))
          enter(CrwState::kLeaveNest);
        else if (ground != kNest)
          enter(CrwState::kTransport);
        break;
      case CrwState::kLeaveNest:
        if (ground != kNest) enter(CrwState::kExplore);
        break;
      case CrwState::kCount:
        break;
    }
    // Actions of the state the robot is now in.
    WheelSpeeds w;
    uint8_t request = kNone;
    switch (state) {
      case CrwState::kPickup:
        request = kPickup;  // stopped on the block
        break;
      case CrwState::kDrop:
        request = kDrop;
        break;
      case CrwState::kTransport: {
        const Vec2 light(s.light_x[i], s.light_y[i]);
        const double len = light.norm();
        const Vec2 photo =
            len > 1e-9 ? Vec2(light / len * config_.phototaxis_force) : wander(l, tick, threat);
        w = steer(photo + avoid, config_.drive, /*soft_only=*/true);
        break;
      }
      default:
        w = steer(wander(l, tick, threat) + avoid, config_.drive, false);
        break;
    }
    out.left[l] = w.left;
    out.right[l] = w.right;
    out.request[l] = request;
    state_[l] = static_cast<uint8_t>(state);
    ++state_ticks_[l];
    ++status.state_counts[state_[l]];
    status.in_avoidance += threat ? 1 : 0;
  }
}

}  // namespace swarm_forage
