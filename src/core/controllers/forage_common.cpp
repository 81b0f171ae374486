#include "swarm_forage/core/controllers/forage_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

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
/// wanderForce() of the 4K robots robots[0..4K), as K interleaved groups of 4 lanes. Inputs are gathered
/// into registers, not through a buffer (4 narrow stores read back as one vector stall store forwarding).
template <int K>
SWARM_FORAGE_LANES void wanderForcesN(const uint32_t* robots, float* angle, const double* step, Vec2* force,
                                      const CrwConfig& c) {
  using namespace lanes;
  D<K> a, st;
  for (int k = 0; k < K; ++k) {
    const uint32_t* g = robots + 4 * k;
    const uint32_t r0 = g[0], r1 = g[1], r2 = g[2], r3 = g[3];
    a.v[k] = _mm256_cvtps_pd(_mm_setr_ps(angle[r0], angle[r1], angle[r2], angle[r3]));
    st.v[k] = _mm256_setr_pd(step[r0], step[r1], step[r2], step[r3]);
  }
  D<K> sa, ca;
  fastSinCosN<K>(a, sa, ca);
  const D<K> radius = set1<K>(c.wander_circle_radius);
  const D<K> x = radius * ca - set1<K>(c.wander_circle_distance), y = radius * sa;
  const D<K> scale = set1<K>(c.wander_force) / sqrt(x * x + y * y);
  // nextWanderAngle without fmod's call and branch: for limit <= |next| < 2 limit, fmod(next, limit) is
  // |next| - limit (exact) with the sign of next; farther out (no draw reaches it by default) fmod itself.
  const D<K> next = a + st;
  const D<K> sign = set1<K>(-0.0), limit = set1<K>(c.wander_limit);
  const D<K> mag = andNot(sign, next);
  const D<K> turned = blend((mag - limit) ^ (next & sign), next, cmp<_CMP_LT_OQ>(mag, limit));
  const D<K> far = cmp<_CMP_NLT_UQ>(mag, set1<K>(2 * c.wander_limit));
  const D<K> fx = x * scale, fy = y * scale;
  for (int k = 0; k < K; ++k) {
    const int far4 = _mm256_movemask_pd(far.v[k]);
    alignas(32) double ox[4], oy[4], nx[4];
    alignas(16) float na[4];
    _mm256_store_pd(ox, fx.v[k]);
    _mm256_store_pd(oy, fy.v[k]);
    _mm_store_ps(na, _mm256_cvtpd_ps(turned.v[k]));
    if (far4) _mm256_store_pd(nx, next.v[k]);
    for (int j = 0; j < 4; ++j) {
      const uint32_t l = robots[4 * k + j];
      force[l] = Vec2(ox[j], oy[j]);
      angle[l] = far4 & (1 << j) ? static_cast<float>(std::fmod(nx[j], c.wander_limit)) : na[j];
    }
  }
}
/// Groups per call: 2 and 4 measure alike in CRW profiles (3.4-4.2 % of it, run to run), 1 took 4.2-4.4 %.
constexpr int kWanderGroups = 2;
SWARM_FORAGE_AVX2 void wanderForcesWide(const uint32_t* robots, float* angle, const double* step, Vec2* force,
                                        const CrwConfig& c) {
  wanderForcesN<kWanderGroups>(robots, angle, step, force, c);
}
SWARM_FORAGE_AVX2 void wanderForces4(const uint32_t* robots, float* angle, const double* step, Vec2* force,
                                     const CrwConfig& c) {
  wanderForcesN<1>(robots, angle, step, force, c);
}
}  // namespace

void wanderForces(const uint32_t* robots, std::size_t n, float* angle, const double* step, Vec2* force,
                  const CrwConfig& c) {
  std::size_t k = 0;
  if (simdEnabled()) {
    for (; k + 4 * kWanderGroups <= n; k += 4 * kWanderGroups)
      wanderForcesWide(robots + k, angle, step, force, c);
    for (; k + 4 <= n; k += 4) wanderForces4(robots + k, angle, step, force, c);
  }
  for (; k < n; ++k) force[robots[k]] = wanderForce(angle[robots[k]], step[robots[k]], c);
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

namespace {
/// The scalar motionForces() of robot l.
inline void motionForceOf(uint32_t l, const uint8_t* motion, const uint8_t* slow, const SensorData& s,
                          uint32_t first_id, const CrwConfig& c, Vec2* force, uint8_t* soft) {
  if (motion[l] > static_cast<uint8_t>(Motion::kLeaveNest)) return;
  bool soft_only = false;
  force[l] =
      motionForce(static_cast<Motion>(motion[l]), s, first_id + l, force[l], c, slow[l] != 0, soft_only);
  soft[l] = soft_only ? kSteerSoft : kSteerFree;
}

/// Lanes of 4 bytes as 64-bit integers.
SWARM_FORAGE_AVX2 inline __m256i bytes4(const uint8_t* p) {
  int32_t v;
  std::memcpy(&v, p, sizeof v);
  return _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(v));
}

/// All ones in the lanes of v equal to k.
SWARM_FORAGE_AVX2 inline __m256d laneIs(const __m256i& v, uint8_t k) {
  return _mm256_castsi256_pd(_mm256_cmpeq_epi64(v, _mm256_set1_epi64x(k)));
}

/// motionForces() of robots l .. l + 4K - 1 (K interleaved groups of 4): every motion's force computed, the
/// robot's own selected. Used with one group: 2 or 4 took more of a CRW profile (its chains are short).
template <int K>
SWARM_FORAGE_LANES void motionForcesN(uint32_t l, const uint8_t* motion, const uint8_t* slow,
                                      const SensorData& s, uint32_t first_id, const CrwConfig& c, Vec2* force,
                                      uint8_t* soft) {
  using namespace lanes;
  const uint32_t i = first_id + l;
  D<K> calm, fast, transport, nest, leave, still, ox, oy, lx, ly, wx, wy;
  for (int k = 0; k < K; ++k) {
    const __m256i m = bytes4(motion + l + 4 * k);
    calm.v[k] = laneIs(bytes4(&s.threatened[i + 4 * k]), 0);
    fast.v[k] = laneIs(bytes4(slow + l + 4 * k), 0);
    transport.v[k] = laneIs(m, static_cast<uint8_t>(Motion::kTransport));
    nest.v[k] = laneIs(m, static_cast<uint8_t>(Motion::kNestWander));
    leave.v[k] = laneIs(m, static_cast<uint8_t>(Motion::kLeaveNest));
    still.v[k] = _mm256_castsi256_pd(
        _mm256_cmpgt_epi64(m, _mm256_set1_epi64x(static_cast<long long>(Motion::kLeaveNest))));
    ox.v[k] = _mm256_cvtps_pd(_mm_loadu_ps(&s.obstacle_x[i + 4 * k]));
    oy.v[k] = _mm256_cvtps_pd(_mm_loadu_ps(&s.obstacle_y[i + 4 * k]));
    lx.v[k] = _mm256_cvtps_pd(_mm_loadu_ps(&s.light_x[i + 4 * k]));
    ly.v[k] = _mm256_cvtps_pd(_mm_loadu_ps(&s.light_y[i + 4 * k]));
    // The wander forces, x0 y0 x1 y1 | x2 y2 x3 y3 to x and y lanes.
    const auto* f = reinterpret_cast<const double*>(force + l + 4 * k);
    const __m256d fa = _mm256_loadu_pd(f), fb = _mm256_loadu_pd(f + 4);
    wx.v[k] = _mm256_permute4x64_pd(_mm256_unpacklo_pd(fa, fb), 0xD8);
    wy.v[k] = _mm256_permute4x64_pd(_mm256_unpackhi_pd(fa, fb), 0xD8);
  }
  const D<K> tiny = set1<K>(1e-9), sign = set1<K>(-0.0), ones = asDouble(set1i<K>(-1));
  const D<K> threat = andNot(calm, ones);
  // avoidanceForce: -ob / |ob| * avoidance_force when threatened and |ob| > 1e-9, else 0.
  const D<K> olen = sqrt(ox * ox + oy * oy);
  const D<K> avoid_on = threat & cmp<_CMP_GT_OQ>(olen, tiny);
  const D<K> af = set1<K>(c.avoidance_force);
  const D<K> ax = avoid_on & ((ox ^ sign) / olen * af), ay = avoid_on & ((oy ^ sign) / olen * af);
  // Phototaxis: light / |light| * phototaxis_force, or (phototaxis_force, 0) with no light.
  const D<K> llen = sqrt(lx * lx + ly * ly);
  const D<K> lit = cmp<_CMP_GT_OQ>(llen, tiny), pf = set1<K>(c.phototaxis_force);
  const D<K> px = blend(pf, lx / llen * pf, lit), py = lit & (ly / llen * pf);
  // Transport: photo + wander when slow and unthreatened, else photo + avoid.
  const D<K> calm_slow = andNot(threat | fast, ones);
  const D<K> tx = px + blend(ax, wx, calm_slow), ty = py + blend(ay, wy, calm_slow);
  // Leave nest: wander + avoid; explore: (wander + avoid) x (1 when threatened, else wander_free_scale).
  const D<K> sx = wx + ax, sy = wy + ay;
  const D<K> k1 = blend(set1<K>(c.wander_free_scale), set1<K>(1.0), threat);
  D<K> x = sx * k1, y = sy * k1;                                                     // explore
  x = blend(blend(blend(blend(x, sx, leave), wx, nest), tx, transport), wx, still);  // still: unchanged
  y = blend(blend(blend(blend(y, sy, leave), wy, nest), ty, transport), wy, still);
  for (int k = 0; k < K; ++k) {
    auto* f = reinterpret_cast<double*>(force + l + 4 * k);
    const __m256d lo = _mm256_unpacklo_pd(x.v[k], y.v[k]), hi = _mm256_unpackhi_pd(x.v[k], y.v[k]);
    _mm256_storeu_pd(f, _mm256_permute2f128_pd(lo, hi, 0x20));  // x0 y0 x2 y2, x1 y1 x3 y3 to pairs
    _mm256_storeu_pd(f + 4, _mm256_permute2f128_pd(lo, hi, 0x31));
  }
  for (uint32_t k4 = l; k4 < l + 4 * K; ++k4)
    if (motion[k4] <= static_cast<uint8_t>(Motion::kLeaveNest))
      soft[k4] = motion[k4] == static_cast<uint8_t>(Motion::kTransport) ? kSteerSoft : kSteerFree;
}
SWARM_FORAGE_AVX2 void motionForces4(uint32_t l, const uint8_t* motion, const uint8_t* slow,
                                     const SensorData& s, uint32_t first_id, const CrwConfig& c, Vec2* force,
                                     uint8_t* soft) {
  motionForcesN<1>(l, motion, slow, s, first_id, c, force, soft);
}
}  // namespace

void motionForces(const uint8_t* motion, const uint8_t* slow, const SensorData& s, uint32_t first_id,
                  uint32_t n, const CrwConfig& c, Vec2* force, uint8_t* soft) {
  uint32_t l = 0;
  if (simdEnabled())
    for (; l + 4 <= n; l += 4) motionForces4(l, motion, slow, s, first_id, c, force, soft);
  for (; l < n; ++l) motionForceOf(l, motion, slow, s, first_id, c, force, soft);
}

WheelSpeeds motionWheels(Motion m, const SensorData& s, uint32_t i, float& angle, CounterRng& rng,
                         const CrwConfig& c, bool slow) {
  const Vec2 wander = motionWanders(m, s, i, slow) ? wanderForce(angle, rng, c) : Vec2(0, 0);
  bool soft_only = false;
  const Vec2 force = motionForce(m, s, i, wander, c, slow, soft_only);
  return steer(force, c.drive, soft_only);
}

}  // namespace swarm_forage
