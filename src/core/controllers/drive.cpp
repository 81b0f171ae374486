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

/// std::clamp(v, lo, hi) per lane: lo below lo, else hi above hi.
SWARM_FORAGE_AVX2 inline void clamp4(__m256d& v, const __m256d& lo, const __m256d& hi) {
  const __m256d upper = _mm256_blendv_pd(v, hi, _mm256_cmp_pd(hi, v, _CMP_LT_OQ));
  v = _mm256_blendv_pd(upper, lo, _mm256_cmp_pd(v, lo, _CMP_LT_OQ));
}

/// steer() of 4 robots, branches as selects.
SWARM_FORAGE_AVX2 void steer4(const Vec2* force, const uint8_t* mode, WheelSpeeds* wheels,
                              const DriveConfig& cfg) {
  const auto* f = reinterpret_cast<const double*>(force);
  const __m256d a = _mm256_loadu_pd(f), b = _mm256_loadu_pd(f + 4);  // x0 y0 x1 y1, x2 y2 x3 y3
  const __m256d x = _mm256_permute4x64_pd(_mm256_unpacklo_pd(a, b), 0xD8);
  const __m256d y = _mm256_permute4x64_pd(_mm256_unpackhi_pd(a, b), 0xD8);
  const __m256d v = _mm256_mul_pd(_mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y))),
                                  _mm256_set1_pd(0.01));
  const __m256d zero = _mm256_setzero_pd();
  __m256d err;
  fastAtan2_4(y, x, err);
  const __m256d abs_err = _mm256_andnot_pd(_mm256_set1_pd(-0.0), err);
  int32_t m4;
  std::memcpy(&m4, mode, sizeof m4);
  const __m256i m = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(m4));
  const __m256d soft_only = _mm256_castsi256_pd(_mm256_cmpeq_epi64(m, _mm256_set1_epi64x(kSteerSoft)));
  const __m256d none = _mm256_castsi256_pd(_mm256_cmpeq_epi64(m, _mm256_set1_epi64x(kSteerNone)));
  const __m256d stm = _mm256_set1_pd(cfg.soft_turn_max);
  const __m256d soft = _mm256_or_pd(_mm256_cmp_pd(abs_err, stm, _CMP_LE_OQ), soft_only);
  const __m256d fr = _mm256_div_pd(_mm256_sub_pd(stm, abs_err), stm);
  const __m256d lo = _mm256_set1_pd(-cfg.max_speed), hi = _mm256_set1_pd(cfg.max_speed);
  __m256d inner = _mm256_blendv_pd(_mm256_set1_pd(-cfg.hard_turn_speed), _mm256_mul_pd(v, fr), soft);
  __m256d outer = _mm256_blendv_pd(_mm256_set1_pd(cfg.hard_turn_speed),
                                   _mm256_mul_pd(v, _mm256_sub_pd(_mm256_set1_pd(2.0), fr)), soft);
  clamp4(inner, lo, hi);
  clamp4(outer, lo, hi);
  const __m256d left_outer = _mm256_cmp_pd(err, zero, _CMP_NGE_UQ);  // err < 0 (err >= 0 picks inner)
  const __m256d off = _mm256_or_pd(none, _mm256_cmp_pd(v, _mm256_set1_pd(1e-9), _CMP_LT_OQ));
  const __m128 l = _mm256_cvtpd_ps(_mm256_andnot_pd(off, _mm256_blendv_pd(inner, outer, left_outer)));
  const __m128 r = _mm256_cvtpd_ps(_mm256_andnot_pd(off, _mm256_blendv_pd(outer, inner, left_outer)));
  auto* w = reinterpret_cast<float*>(wheels);
  _mm_storeu_ps(w, _mm_unpacklo_ps(l, r));
  _mm_storeu_ps(w + 4, _mm_unpackhi_ps(l, r));
}

}  // namespace

void steerAll(const Vec2* force, const uint8_t* mode, WheelSpeeds* wheels, std::size_t n,
              const DriveConfig& cfg) {
  std::size_t k = 0;
  if (simdEnabled())
    for (; k + 4 <= n; k += 4) steer4(force + k, mode + k, wheels + k, cfg);
  for (; k < n; ++k)
    wheels[k] = mode[k] == kSteerNone ? WheelSpeeds{} : steer(force[k], cfg, mode[k] == kSteerSoft);
}

}  // namespace swarm_forage
