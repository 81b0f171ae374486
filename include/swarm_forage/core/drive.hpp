#pragma once
// Turns a steering force (robot frame, cm/s as in FORDYCA) into differential-drive wheel speeds.
#include "swarm_forage/core/geometry.hpp"

namespace swarm_forage {

struct DriveConfig {
  double max_speed = 0.1;                // per wheel [m/s]
  double soft_turn_max = deg2rad(15.0);  // heading errors up to this turn softly
  double hard_turn_speed = 0.05;         // wheel speed when turning in place [m/s]
};

struct WheelSpeeds {
  float left = 0, right = 0;
};

/// Soft turn when |heading error| <= soft_turn_max (wheels v*f, v*(2-f)), otherwise turn in place
/// (or, with soft_only, pivot on the inner wheel). Wheel speeds never exceed max_speed.
WheelSpeeds steer(const Vec2& force_cm, const DriveConfig& cfg, bool soft_only);

}  // namespace swarm_forage
