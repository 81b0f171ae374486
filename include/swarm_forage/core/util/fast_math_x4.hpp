#pragma once
// fastSinCos and fastAtan2 on 4 lanes (AVX2, never FMA): the very same operations in the same order, so
// every lane has the bits of the scalar function (IEEE +, -, *, / round each lane as the scalar ones; selects
// and sign-bit xors replace the scalar code's selects). Only for callers that checked simdEnabled().
#include <immintrin.h>

#include "swarm_forage/core/util/fast_math.hpp"

// A function that may use AVX2 (and inline the functions below); FMA stays off, so no contraction. Vectors
// go by reference: passed by value, GCC may warn that their ABI depends on AVX (-Wpsabi).
#define SWARM_FORAGE_AVX2 __attribute__((target("avx2")))

namespace swarm_forage {

/// fastSinCos(a[k], s[k], c[k]) for the 4 lanes.
SWARM_FORAGE_AVX2 inline void fastSinCos4(const __m256d& a, __m256d& s, __m256d& c) {
  const __m256d k = _mm256_round_pd(
      _mm256_add_pd(_mm256_mul_pd(a, _mm256_set1_pd(0.63661977236758134308)), _mm256_set1_pd(0.5)),
      _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  const __m256d r =
      _mm256_sub_pd(_mm256_sub_pd(_mm256_sub_pd(a, _mm256_mul_pd(k, _mm256_set1_pd(1.57079625129699707031))),
                                  _mm256_mul_pd(k, _mm256_set1_pd(7.54978941586159635336e-8))),
                    _mm256_mul_pd(k, _mm256_set1_pd(5.39030285815811905290e-15)));
  const __m256d z = _mm256_mul_pd(r, r);
  __m256d ps = _mm256_sub_pd(_mm256_mul_pd(_mm256_set1_pd(1.58962301576546568060e-10), z),
                             _mm256_set1_pd(2.50507477628578072866e-8));
  ps = _mm256_add_pd(_mm256_mul_pd(ps, z), _mm256_set1_pd(2.75573136213857245213e-6));
  ps = _mm256_sub_pd(_mm256_mul_pd(ps, z), _mm256_set1_pd(1.98412698295895385996e-4));
  ps = _mm256_add_pd(_mm256_mul_pd(ps, z), _mm256_set1_pd(8.33333333332211858878e-3));
  ps = _mm256_sub_pd(_mm256_mul_pd(ps, z), _mm256_set1_pd(1.66666666666666307295e-1));
  const __m256d sr = _mm256_add_pd(r, _mm256_mul_pd(_mm256_mul_pd(r, z), ps));
  __m256d pc = _mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(-1.13585365213876817300e-11), z),
                             _mm256_set1_pd(2.08757008419747316778e-9));
  pc = _mm256_sub_pd(_mm256_mul_pd(pc, z), _mm256_set1_pd(2.75573141792967388112e-7));
  pc = _mm256_add_pd(_mm256_mul_pd(pc, z), _mm256_set1_pd(2.48015872888517045348e-5));
  pc = _mm256_sub_pd(_mm256_mul_pd(pc, z), _mm256_set1_pd(1.38888888888730564116e-3));
  pc = _mm256_add_pd(_mm256_mul_pd(pc, z), _mm256_set1_pd(4.16666666666665929218e-2));
  const __m256d cr = _mm256_add_pd(_mm256_sub_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(_mm256_set1_pd(0.5), z)),
                                   _mm256_mul_pd(_mm256_mul_pd(z, z), pc));
  // The quadrant k mod 4, exact for any k (k / 4 and its floor are exact), as static_cast<long long>(k) & 3
  // gives it; NaN and infinity convert to 0x80000000 and so give quadrant 0 as the scalar cast does.
  const __m256d k4 = _mm256_sub_pd(
      k, _mm256_mul_pd(_mm256_set1_pd(4.0), _mm256_round_pd(_mm256_mul_pd(k, _mm256_set1_pd(0.25)),
                                                            _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)));
  const __m256i q = _mm256_cvtepi32_epi64(_mm256_cvtpd_epi32(k4));
  const __m256i one = _mm256_set1_epi64x(1), two = _mm256_set1_epi64x(2);
  const __m256d swap =
      _mm256_castsi256_pd(_mm256_sub_epi64(_mm256_setzero_si256(), _mm256_and_si256(q, one)));
  const __m256d ssign = _mm256_castsi256_pd(_mm256_slli_epi64(_mm256_and_si256(q, two), 62));
  const __m256d csign =
      _mm256_castsi256_pd(_mm256_slli_epi64(_mm256_and_si256(_mm256_add_epi64(q, one), two), 62));
  s = _mm256_xor_pd(_mm256_blendv_pd(sr, cr, swap), ssign);
  c = _mm256_xor_pd(_mm256_blendv_pd(cr, sr, swap), csign);
}

/// out = fastAtan2(y[k], x[k]) for the 4 lanes (0 for (+-0, +-0), as the scalar one).
SWARM_FORAGE_AVX2 inline void fastAtan2_4(const __m256d& y, const __m256d& x, __m256d& out) {
  constexpr double kPiHalf = 1.57079632679489661923, kPiQuarter = 0.78539816339744830962;
  const __m256d sign = _mm256_set1_pd(-0.0), zero = _mm256_setzero_pd();
  const __m256d ax = _mm256_andnot_pd(sign, x), ay = _mm256_andnot_pd(sign, y);
  const __m256d both0 =
      _mm256_and_pd(_mm256_cmp_pd(ax, zero, _CMP_EQ_OQ), _mm256_cmp_pd(ay, zero, _CMP_EQ_OQ));
  const __m256d swap = _mm256_cmp_pd(ay, ax, _CMP_GT_OQ);
  const __m256d lo = _mm256_blendv_pd(ay, ax, swap), hi = _mm256_blendv_pd(ax, ay, swap);
  const __m256d mid = _mm256_cmp_pd(lo, _mm256_mul_pd(_mm256_set1_pd(0.66), hi), _CMP_GT_OQ);
  // One division: the scalar code's (lo - hi) / (lo + hi) or lo / hi, whichever the lane takes.
  const __m256d t = _mm256_div_pd(_mm256_blendv_pd(lo, _mm256_sub_pd(lo, hi), mid),
                                  _mm256_blendv_pd(hi, _mm256_add_pd(lo, hi), mid));
  const __m256d base = _mm256_and_pd(mid, _mm256_set1_pd(kPiQuarter));
  const __m256d more = _mm256_and_pd(mid, _mm256_set1_pd(0.5 * 6.123233995736765886130e-17));
  const __m256d z = _mm256_mul_pd(t, t);
  __m256d p = _mm256_sub_pd(_mm256_mul_pd(_mm256_set1_pd(-8.750608600031904122785e-1), z),
                            _mm256_set1_pd(1.615753718733365076637e1));
  p = _mm256_sub_pd(_mm256_mul_pd(p, z), _mm256_set1_pd(7.500855792314704667340e1));
  p = _mm256_sub_pd(_mm256_mul_pd(p, z), _mm256_set1_pd(1.228866684490136173410e2));
  p = _mm256_sub_pd(_mm256_mul_pd(p, z), _mm256_set1_pd(6.485021904942025371773e1));
  __m256d q = _mm256_add_pd(z, _mm256_set1_pd(2.485846490142306297962e1));
  q = _mm256_add_pd(_mm256_mul_pd(q, z), _mm256_set1_pd(1.650270098316988542046e2));
  q = _mm256_add_pd(_mm256_mul_pd(q, z), _mm256_set1_pd(4.328810604912902668951e2));
  q = _mm256_add_pd(_mm256_mul_pd(q, z), _mm256_set1_pd(4.853903996359136964868e2));
  q = _mm256_add_pd(_mm256_mul_pd(q, z), _mm256_set1_pd(1.945506571482613964425e2));
  __m256d a = _mm256_div_pd(_mm256_mul_pd(_mm256_mul_pd(t, z), p), q);
  a = _mm256_add_pd(base, _mm256_add_pd(_mm256_add_pd(a, t), more));
  a = _mm256_blendv_pd(a, _mm256_sub_pd(_mm256_set1_pd(kPiHalf), a), swap);
  a = _mm256_blendv_pd(a, _mm256_sub_pd(_mm256_set1_pd(2 * kPiHalf), a), _mm256_cmp_pd(x, zero, _CMP_LT_OQ));
  a = _mm256_xor_pd(a, _mm256_and_pd(y, sign));
  out = _mm256_andnot_pd(both0, a);  // +0 where both are zero
}

}  // namespace swarm_forage
