#include "swarm_forage/core/controllers/drive.hpp"

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/util/fast_math.hpp"

namespace swarm_forage {

WheelSpeeds steer(const Vec2& force_cm, const DriveConfig& cfg, bool soft_only) {
  const double v = force_cm.norm() * 0.01;  // cm/s -> m/s
  if (v < 1e-9) return {};
  const double err = fastAtan2(force_cm.y(), force_cm.x());
  const double abs_err = std::fabs(err);
  double inner, outer;
  if (abs_err <= cfg.soft_turn_max || soft_only) {
    const double f = (cfg.soft_turn_max - abs_err) / cfg.soft_turn_max;
    inner = v * f;
    outer = v * (2.0 - f);
  } else {
    inner = -cfg.hard_turn_speed;
    outer = cfg.hard_turn_speed;
  }
  inner = std::clamp(inner, -cfg.max_speed, cfg.max_speed);  // rcppsw differential_drive::limit()
  outer = std::clamp(outer, -cfg.max_speed, cfg.max_speed);
  // A positive error (target to the left) needs the right wheel to be the outer one.
  return err >= 0 ? WheelSpeeds{static_cast<float>(inner), static_cast<float>(outer)}
                  : WheelSpeeds{static_cast<float>(outer), static_cast<float>(inner)};
}

}  // namespace swarm_forage
