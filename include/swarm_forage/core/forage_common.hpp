#pragma once
// What every forager shares (DESIGN section 4): the CRW exploration/transport constants, the motion
// primitives (correlated random walk, obstacle avoidance, phototaxis) and the nest-delivery sequence
// transport -> nest wander -> drop -> leave nest -> explore. Used by CRW, DPO and GP-DPO so that they
// explore and transport identically.
#include <cstdint>

#include "swarm_forage/core/drive.hpp"
#include "swarm_forage/core/geometry.hpp"
#include "swarm_forage/core/rng.hpp"
#include "swarm_forage/core/sensing.hpp"

namespace swarm_forage {

/// CRW exploration and transport constants (forces in cm/s as in FORDYCA).
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

/// Throws ParameterError(what) unless ok.
void requireParameter(bool ok, const char* what);

/// -(closest threatening obstacle) scaled to `force` (robot frame, cm/s); zero when none threatens.
Vec2 avoidanceForce(const SensorData& s, uint32_t i, double force);

/// Advances a wander angle by one draw of `rng` and returns the wander force (robot frame, cm/s).
Vec2 wanderForce(float& angle, CounterRng& rng, const CrwConfig& c, bool threatened);

/// Force toward the sum of the light vectors; wanders (one draw) when no light is sensed.
Vec2 phototaxisForce(const SensorData& s, uint32_t i, float& angle, CounterRng& rng, const CrwConfig& c,
                     bool threatened);

/// Wander plus avoidance, hard turns allowed (explore, nest wander, leave nest).
inline WheelSpeeds wanderWheels(float& angle, CounterRng& rng, const CrwConfig& c, bool threatened,
                                const Vec2& avoid) {
  return steer(wanderForce(angle, rng, c, threatened) + avoid, c.drive, false);
}

/// Phototaxis plus avoidance with soft turns only (transport to the nest).
inline WheelSpeeds transportWheels(const SensorData& s, uint32_t i, float& angle, CounterRng& rng,
                                   const CrwConfig& c, bool threatened, const Vec2& avoid) {
  return steer(phototaxisForce(s, i, angle, rng, c, threatened) + avoid, c.drive, true);
}

/// The nest-delivery transitions shared by every forager, for any state enum with the enumerators
/// kTransport, kNestWander, kDrop, kLeaveNest and kExplore: transport until the nest, wander there
/// `nest_wander_ticks`, drop, leave the nest, explore; back to transport when the nest is left early.
/// Returns true when the state changed (the caller restarts its state clock). Other states: no-op.
template <class State>
bool deliveryTransition(State& state, uint32_t state_ticks, uint8_t ground, bool carrying, uint8_t events,
                        uint32_t nest_wander_ticks) {
  const State before = state;
  switch (state) {
    case State::kTransport:
      if (ground == kNest) state = State::kNestWander;
      break;
    case State::kNestWander:
      if (ground != kNest)
        state = State::kTransport;
      else if (state_ticks >= nest_wander_ticks)
        state = State::kDrop;
      break;
    case State::kDrop:
      if (!carrying || (events & kDropDone))
        state = State::kLeaveNest;
      else if (ground != kNest)
        state = State::kTransport;
      break;
    case State::kLeaveNest:
      if (ground != kNest) state = State::kExplore;
      break;
    default:
      break;
  }
  return state != before;
}

}  // namespace swarm_forage
