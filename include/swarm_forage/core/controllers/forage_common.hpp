#pragma once
// What every forager shares (docs/design-model.md, Controllers): the CRW exploration/transport constants, the
// motion primitives (correlated random walk, obstacle avoidance, phototaxis) and the nest-delivery sequence
// transport -> nest wander -> drop -> leave nest -> explore. Used by CRW, DPO and GP-DPO so that they
// explore and transport identically.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "swarm_forage/core/controllers/drive.hpp"
#include "swarm_forage/core/util/geometry.hpp"
#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/fordyca_quirks.hpp"
#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

class StateArchive;

/// CRW exploration and transport constants (forces in cm/s as in FORDYCA).
struct CrwConfig {
  double wander_step =
      deg2rad(5.0);  // wander angle a <- fmod(a + U[-step, step], limit): a wrap, not a clamp
  double wander_limit = deg2rad(5.0);   // (rcppsw wander_force max_angle_delta)
  double wander_circle_distance = 4.0;  // the force points from a circle this far ahead ...
  double wander_circle_radius =
      100.0;                       // ... to the point at angle a on its rim (about 1.04 a off the heading)
  double wander_force = 9.0;       // cm/s
  double wander_free_scale = 0.7;  // exploring with no obstacle threatening: the summed force x this
  double avoidance_force = 8.0;
  double phototaxis_force = 8.0;
  uint32_t nest_wander_ticks = 25;  // wander in the nest before dropping
  uint32_t min_explore_ticks = 50;
  DriveConfig drive;
  /// FORDYCA 2019's controller-side quirks (ControllerConfigs::quirks.controllerSide(); not a YAML key).
  FordycaQuirks quirks;

  void validate() const;  // throws ParameterError
};

/// Which robots of a batch stand still: not moved 1 cm for 50 ticks or more (turning in place included).
class StallTracker {
 public:
  static constexpr uint32_t kTicks = 50;
  static constexpr float kDistance = 0.01f;
  explicit StallTracker(uint32_t count) : x_(count, 0.f), y_(count, 0.f), since_(count, kUnseen) {}
  /// The tracker's arrays, for a loop over the batch (pointers taken once).
  struct Arrays {
    float* x;
    float* y;
    uint64_t* since;
    /// Observes robot `local` at (px, py) in `tick`; true when it is stalled.
    bool stalled(uint32_t local, float px, float py, uint64_t tick) const {
      const float dx = px - x[local], dy = py - y[local];
      if (since[local] == kUnseen || tick < since[local] || dx * dx + dy * dy > kDistance * kDistance) {
        x[local] = px;
        y[local] = py;
        since[local] = tick;
      }
      return tick - since[local] >= kTicks;
    }
  };
  Arrays arrays() { return {x_.data(), y_.data(), since_.data()}; }
  bool stalled(uint32_t local, float x, float y, uint64_t tick) {
    return arrays().stalled(local, x, y, tick);
  }
  void forget(uint32_t local) { since_[local] = kUnseen; }
  void persist(StateArchive& a, uint32_t local);  // controller_checkpoint.cpp

 private:
  static constexpr uint64_t kUnseen = ~0ULL;
  std::vector<float> x_, y_;
  std::vector<uint64_t> since_;  // the tick the robot was last seen moving away from (x_, y_)
};

/// Throws ParameterError(what) unless ok.
void requireParameter(bool ok, const char* what);

/// -(closest threatening obstacle) scaled to `force` (robot frame, cm/s); zero when none threatens.
Vec2 avoidanceForce(const SensorData& s, uint32_t i, double force);

/// The wander force of magnitude wander_force (robot frame, cm/s) for the current wander angle, which
/// then takes one step of `rng` (rcppsw wander_force: the force uses the angle before its update).
Vec2 wanderForce(float& angle, CounterRng& rng, const CrwConfig& c);
/// The same with the draw taken beforehand: `step` = rng.uniform(-wander_step, wander_step).
Vec2 wanderForce(float& angle, double step, const CrwConfig& c);
/// force[l] = wanderForce(angle[l], step[l], c) for each l of robots[0 .. n); 4 robots at a time with AVX2
/// where simdEnabled(), the same bits.
void wanderForces(const uint32_t* robots, std::size_t n, float* angle, const double* step, Vec2* force,
                  const CrwConfig& c);

/// How a forager moves in each phase (FORDYCA random_explore_behavior and base_foraging_fsm).
enum class Motion : uint8_t {
  kExplore,     // wander + avoidance (hard turns allowed); with no threat, wander x wander_free_scale
  kTransport,   // phototaxis + avoidance, forced soft turns; no wander (but see motionWheels' `slow`)
  kNestWander,  // wander alone: no avoidance, no scaling
  kLeaveNest,   // wander + avoidance, no scaling (no anti-phototaxis)
};

/// Wheel speeds of robot i moving as `m`; the wander angle steps in every phase but transport. `slow`
/// (kTransportWander: FORDYCA's |linear_velocity()| <= 0.1) adds the wander force to an unthreatened
/// transport (fordyca base_foraging_fsm transport_to_nest), and the wander angle then steps too.
WheelSpeeds motionWheels(Motion m, const SensorData& s, uint32_t i, float& angle, CounterRng& rng,
                         const CrwConfig& c, bool slow = false);
/// motionWheels in two parts, for callers that batch the wander forces: whether `m` takes a wander force
/// (and a draw) for robot i, and the force to steer by given that wander force (zero when it takes none);
/// `soft_only` tells steer() to force soft turns.
inline bool motionWanders(Motion m, const SensorData& s, uint32_t i, bool slow) {
  return m != Motion::kTransport || (slow && s.threatened[i] == 0);
}
Vec2 motionForce(Motion m, const SensorData& s, uint32_t i, const Vec2& wander, const CrwConfig& c, bool slow,
                 bool& soft_only);
/// motionForce() over a batch: for each l < n whose motion[l] is a Motion (any other value: force[l] and
/// soft[l] left as they are), force[l] = motionForce(motion[l], s, first_id + l, force[l], c, slow[l] != 0,
/// soft_only) and soft[l] = soft_only ? kSteerSoft : kSteerFree; 4 robots at a time with AVX2 where
/// simdEnabled(), the same bits.
void motionForces(const uint8_t* motion, const uint8_t* slow, const SensorData& s, uint32_t first_id,
                  uint32_t n, const CrwConfig& c, Vec2* force, uint8_t* soft);

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
