#include "swarm_forage/core/controllers/forage_common.hpp"

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/util/fast_math.hpp"
#include "swarm_forage/core/util/fast_math_x4.hpp"
#include "swarm_forage/core/util/simd.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

void requireParameter(bool ok, const char* what) {
  if (!ok) throw ParameterError(what);
}

void CrwConfig::validate() const {
  const auto require = requireParameter;
  require(wander_step >= 0 && wander_step <= kPi, "crw/wander_step_deg must be in [0, 180]");
  require(wander_limit > 0 && wander_limit <= kPi, "crw/wander_limit_deg must be in (0, 180]");
  require(wander_circle_distance >= 0 && wander_circle_distance <= 1000,
          "crw/wander_circle_distance must be in [0, 1000]");
  require(wander_circle_radius > wander_circle_distance && wander_circle_radius <= 10000,
          "crw/wander_circle_radius must be in (wander_circle_distance, 10000]");
  require(wander_force > 0 && wander_force <= 100, "crw/wander_force must be in (0, 100] cm/s");
  require(wander_free_scale > 0 && wander_free_scale <= 1, "crw/wander_free_scale must be in (0, 1]");
  require(avoidance_force >= 0 && avoidance_force <= 100, "crw/avoidance_force must be in [0, 100] cm/s");
  require(phototaxis_force > 0 && phototaxis_force <= 100, "crw/phototaxis_force must be in (0, 100] cm/s");
  require(nest_wander_ticks <= 100000, "crw/nest_wander_ticks must be in [0, 100000]");
  require(min_explore_ticks <= 100000, "crw/min_explore_ticks must be in [0, 100000]");
  require(drive.max_speed > 0 && drive.max_speed <= 1, "crw/max_speed must be in (0, 1] m/s");
  require(drive.soft_turn_max > 0 && drive.soft_turn_max < kPi, "crw/soft_turn_max_deg must be in (0, 180)");
  require(drive.hard_turn_speed > 0 && drive.hard_turn_speed <= drive.max_speed,
          "crw/hard_turn_speed must be in (0, max_speed] m/s");
}

Vec2 avoidanceForce(const SensorData& s, uint32_t i, double force) {
  if (!s.threatened[i]) return {0, 0};
  const Vec2 ob(s.obstacle_x[i], s.obstacle_y[i]);
  const double len = ob.norm();
  return len > 1e-9 ? Vec2(-ob / len * force) : Vec2(0, 0);
}

namespace {
// fmod folds the walk back towards 0 at +-limit; a clamp would let it sit at the limit (circling).
inline float nextWanderAngle(double a, double step, const CrwConfig& c) {
  const double next = a + step;
  return static_cast<float>(std::abs(next) < c.wander_limit ? next : std::fmod(next, c.wander_limit));
}
}  // namespace

Vec2 wanderForce(float& angle, CounterRng& rng, const CrwConfig& c) {
  return wanderForce(angle, rng.uniform(-c.wander_step, c.wander_step), c);
}

Vec2 wanderForce(float& angle, double step, const CrwConfig& c) {
  const double a = angle;
  // From the centre of a circle ahead to the point at angle a on its rim.
  double sa, ca;
  fastSinCos(a, sa, ca);
  const double fx = c.wander_circle_radius * ca - c.wander_circle_distance, fy = c.wander_circle_radius * sa;
  const double scale = c.wander_force / std::sqrt(fx * fx + fy * fy);  // the radius exceeds the distance
  angle = nextWanderAngle(a, step, c);
  return {fx * scale, fy * scale};
}

namespace {
/// wanderForce() of the 4 robots robots[0..4).
SWARM_FORAGE_AVX2 void wanderForces4(const uint32_t* robots, float* angle, const double* step, Vec2* force,
                                     const CrwConfig& c) {
  alignas(32) double a[4], fx[4], fy[4];
  for (int k = 0; k < 4; ++k) a[k] = angle[robots[k]];
  __m256d sa, ca;
  fastSinCos4(_mm256_load_pd(a), sa, ca);
  const __m256d x = _mm256_sub_pd(_mm256_mul_pd(_mm256_set1_pd(c.wander_circle_radius), ca),
                                  _mm256_set1_pd(c.wander_circle_distance));
  const __m256d y = _mm256_mul_pd(_mm256_set1_pd(c.wander_circle_radius), sa);
  const __m256d scale =
      _mm256_div_pd(_mm256_set1_pd(c.wander_force),
                    _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y))));
  _mm256_store_pd(fx, _mm256_mul_pd(x, scale));
  _mm256_store_pd(fy, _mm256_mul_pd(y, scale));
  for (int k = 0; k < 4; ++k) {
    const uint32_t l = robots[k];
    force[l] = Vec2(fx[k], fy[k]);
    angle[l] = nextWanderAngle(a[k], step[l], c);
  }
}
}  // namespace

void wanderForces(const uint32_t* robots, std::size_t n, float* angle, const double* step, Vec2* force,
                  const CrwConfig& c) {
  std::size_t k = 0;
  if (simdEnabled())
    for (; k + 4 <= n; k += 4) wanderForces4(robots + k, angle, step, force, c);
  for (; k < n; ++k) force[robots[k]] = wanderForce(angle[robots[k]], step[robots[k]], c);
}

bool motionWanders(Motion m, const SensorData& s, uint32_t i, bool slow) {
  return m != Motion::kTransport || (slow && s.threatened[i] == 0);
}

Vec2 motionForce(Motion m, const SensorData& s, uint32_t i, const Vec2& wander, const CrwConfig& c, bool slow,
                 bool& soft_only) {
  const bool threat = s.threatened[i] != 0;
  const Vec2 avoid = avoidanceForce(s, i, c.avoidance_force);
  soft_only = m == Motion::kTransport;
  switch (m) {
    case Motion::kTransport: {
      const Vec2 light(s.light_x[i], s.light_y[i]);
      const double len = light.norm();
      const Vec2 photo = len > 1e-9 ? Vec2(light / len * c.phototaxis_force) : Vec2(c.phototaxis_force, 0);
      if (slow && !threat) return photo + wander;
      return photo + avoid;
    }
    case Motion::kNestWander:
      return wander;
    case Motion::kLeaveNest:
      return wander + avoid;
    case Motion::kExplore:
    default:
      return (wander + avoid) * (threat ? 1.0 : c.wander_free_scale);
  }
}

WheelSpeeds motionWheels(Motion m, const SensorData& s, uint32_t i, float& angle, CounterRng& rng,
                         const CrwConfig& c, bool slow) {
  const Vec2 wander = motionWanders(m, s, i, slow) ? wanderForce(angle, rng, c) : Vec2(0, 0);
  bool soft_only = false;
  const Vec2 force = motionForce(m, s, i, wander, c, slow, soft_only);
  return steer(force, c.drive, soft_only);
}

}  // namespace swarm_forage
