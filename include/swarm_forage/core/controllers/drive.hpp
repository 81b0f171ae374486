#pragma once
// Turns a steering force (robot frame, cm/s as in FORDYCA) into differential-drive wheel speeds.
#include <cstddef>
#include <cstdint>

#include "swarm_forage/core/util/geometry.hpp"

namespace swarm_forage {

struct DriveConfig {
  double max_speed = 0.1;                // per wheel [m/s]
  double soft_turn_max = deg2rad(15.0);  // heading errors up to this turn softly
  double hard_turn_speed = 0.1;          // wheel speed when turning in place [m/s] (FORDYCA: the limit)
};

struct WheelSpeeds {
  float left = 0, right = 0;
};

/// FORDYCA's differential_drive_fsm: speed v = |force|, heading error = its angle. A soft turn when
/// |error| <= soft_turn_max, or always with soft_only: wheels v f and v (2 - f), f = (soft_turn_max -
/// |error|) / soft_turn_max (negative for a forced soft turn beyond soft_turn_max: the inner wheel
/// reverses). Otherwise a hard turn in place at -+hard_turn_speed. Each wheel is clamped to +-max_speed.
WheelSpeeds steer(const Vec2& force_cm, const DriveConfig& cfg, bool soft_only);

/// How steerAll() drives each robot: steer() with soft_only false or true, or zero wheels.
enum SteerMode : uint8_t { kSteerFree = 0, kSteerSoft = 1, kSteerNone = 2 };
/// wheels[k] = steer(force[k], cfg, mode[k] == kSteerSoft), {} for kSteerNone (force[k] then unread in
/// effect), k < n; 4 robots at a time with AVX2 where simdEnabled(), the same bits.
void steerAll(const Vec2* force, const uint8_t* mode, WheelSpeeds* wheels, std::size_t n,
              const DriveConfig& cfg);

}  // namespace swarm_forage
