#pragma once
#include <Eigen/Core>
#include <cmath>

#include "swarm_forage/core/util/fast_math.hpp"

namespace swarm_forage {

using Vec2 = Eigen::Vector2d;

constexpr double kPi = 3.14159265358979323846;
inline double deg2rad(double deg) { return deg * kPi / 180.0; }

/// Wraps an angle to [-pi, pi).
inline double wrapAngle(double a) {
  if (a >= -kPi && a < kPi) return a;
  a = std::fmod(a + kPi, 2.0 * kPi);
  return a < 0 ? a + kPi : a - kPi;
}

/// Rotates a map-frame vector into the frame of a robot with heading theta.
inline Vec2 toRobotFrame(const Vec2& v, double theta) {
  double s, c;
  fastSinCos(theta, s, c);
  return {c * v.x() + s * v.y(), -s * v.x() + c * v.y()};
}

struct Rect {
  double min_x, min_y, max_x, max_y;
  bool contains(double x, double y) const { return x >= min_x && x <= max_x && y >= min_y && y <= max_y; }
  bool overlaps(const Rect& o) const {
    return min_x < o.max_x && o.min_x < max_x && min_y < o.max_y && o.min_y < max_y;
  }
  double width() const { return max_x - min_x; }
  double height() const { return max_y - min_y; }
  static Rect centered(double cx, double cy, double sx, double sy) {
    return {cx - sx / 2, cy - sy / 2, cx + sx / 2, cy + sy / 2};
  }
};

}  // namespace swarm_forage
