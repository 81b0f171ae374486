#include "swarm_forage/core/controllers/drive.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "swarm_forage/core/util/fast_math.hpp"
#include "swarm_forage/core/util/fast_math_x4.hpp"
#include "swarm_forage/core/util/simd.hpp"

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

namespace {

static_assert(sizeof(Vec2) == 2 * sizeof(double) && sizeof(WheelSpeeds) == 2 * sizeof(float),
              "steer4 reads forces and writes wheels as packed pairs");

/// steer() of K groups of 4 robots, branches as selects, the groups' chains interleaved.
template <int K>
SWARM_FORAGE_LANES void steerLanes(const Vec2* force, const uint8_t* mode, WheelSpeeds* wheels,
                                   const DriveConfig& cfg) {
  using namespace lanes;
  D<K> x, y, soft_only, none;
  for (int k = 0; k < K; ++k) {
    const auto* f = reinterpret_cast<const double*>(force + 4 * k);
    const __m256d a = _mm256_loadu_pd(f), b = _mm256_loadu_pd(f + 4);  // x0 y0 x1 y1, x2 y2 x3 y3
    x.v[k] = _mm256_permute4x64_pd(_mm256_unpacklo_pd(a, b), 0xD8);
    y.v[k] = _mm256_permute4x64_pd(_mm256_unpackhi_pd(a, b), 0xD8);
    int32_t m4;
    std::memcpy(&m4, mode + 4 * k, sizeof m4);
    const __m256i m = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(m4));
    soft_only.v[k] = _mm256_castsi256_pd(_mm256_cmpeq_epi64(m, _mm256_set1_epi64x(kSteerSoft)));
    none.v[k] = _mm256_castsi256_pd(_mm256_cmpeq_epi64(m, _mm256_set1_epi64x(kSteerNone)));
  }
  const D<K> v = sqrt(x * x + y * y) * set1<K>(0.01);
  D<K> err;
  fastAtan2N<K>(y, x, err);
  const D<K> abs_err = andNot(set1<K>(-0.0), err);
  const D<K> stm = set1<K>(cfg.soft_turn_max);
  const D<K> soft = cmp<_CMP_LE_OQ>(abs_err, stm) | soft_only;
  const D<K> fr = (stm - abs_err) / stm;
  const D<K> lo = set1<K>(-cfg.max_speed), hi = set1<K>(cfg.max_speed);
  const D<K> inner = clamp(blend(set1<K>(-cfg.hard_turn_speed), v * fr, soft), lo, hi);
  const D<K> outer = clamp(blend(set1<K>(cfg.hard_turn_speed), v * (set1<K>(2.0) - fr), soft), lo, hi);
  const D<K> left_outer = cmp<_CMP_NGE_UQ>(err, set1<K>(0.0));  // err < 0 (err >= 0 picks inner)
  const D<K> off = none | cmp<_CMP_LT_OQ>(v, set1<K>(1e-9));
  const D<K> left = andNot(off, blend(inner, outer, left_outer));
  const D<K> right = andNot(off, blend(outer, inner, left_outer));
  for (int k = 0; k < K; ++k) {
    const __m128 l = _mm256_cvtpd_ps(left.v[k]), r = _mm256_cvtpd_ps(right.v[k]);
    auto* w = reinterpret_cast<float*>(wheels + 4 * k);
    _mm_storeu_ps(w, _mm_unpacklo_ps(l, r));
    _mm_storeu_ps(w + 4, _mm_unpackhi_ps(l, r));
  }
}

/// steer() of 4 x kSteerGroups robots, and of 4. Groups per call measured in L1 (ns per robot): 1: 5.1,
/// 2: 4.6, 4: 3.6 (more registers spill, but more division chains overlap).
constexpr int kSteerGroups = 4;
SWARM_FORAGE_AVX2 void steerWide(const Vec2* force, const uint8_t* mode, WheelSpeeds* wheels,
                                 const DriveConfig& cfg) {
  steerLanes<kSteerGroups>(force, mode, wheels, cfg);
}
SWARM_FORAGE_AVX2 void steer4(const Vec2* force, const uint8_t* mode, WheelSpeeds* wheels,
                              const DriveConfig& cfg) {
  steerLanes<1>(force, mode, wheels, cfg);
}

}  // namespace

void steerAll(const Vec2* force, const uint8_t* mode, WheelSpeeds* wheels, std::size_t n,
              const DriveConfig& cfg) {
  std::size_t k = 0;
  if (simdEnabled()) {
    for (; k + 4 * kSteerGroups <= n; k += 4 * kSteerGroups) steerWide(force + k, mode + k, wheels + k, cfg);
    for (; k + 4 <= n; k += 4) steer4(force + k, mode + k, wheels + k, cfg);
  }
  for (; k < n; ++k)
    wheels[k] = mode[k] == kSteerNone ? WheelSpeeds{} : steer(force[k], cfg, mode[k] == kSteerSoft);
}

}  // namespace swarm_forage
