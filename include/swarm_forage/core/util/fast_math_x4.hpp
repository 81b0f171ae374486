#pragma once
// fastSinCos and fastAtan2 on 4 lanes (AVX2, never FMA), and on K groups of 4 lanes interleaved
// (lanes_x4.hpp): the very same operations in the same order, so every lane has the bits of the scalar
// function (IEEE +, -,
// *, / round each lane as the scalar ones; selects and sign-bit xors replace the scalar code's selects).
// Only for callers that checked simdEnabled().
#include <immintrin.h>

#include "swarm_forage/core/util/fast_math.hpp"
#include "swarm_forage/core/util/lanes_x4.hpp"

namespace swarm_forage {

/// fastSinCos(a[k], s[k], c[k]) for every lane.
template <int K>
SWARM_FORAGE_LANES void fastSinCosN(const lanes::D<K>& a, lanes::D<K>& s, lanes::D<K>& c) {
  using namespace lanes;
  const D<K> k = floor(a * set1<K>(0.63661977236758134308) + set1<K>(0.5));
  const D<K> r = a - k * set1<K>(1.57079625129699707031) - k * set1<K>(7.54978941586159635336e-8) -
                 k * set1<K>(5.39030285815811905290e-15);
  const D<K> z = r * r;
  D<K> ps = set1<K>(1.58962301576546568060e-10) * z - set1<K>(2.50507477628578072866e-8);
  ps = ps * z + set1<K>(2.75573136213857245213e-6);
  ps = ps * z - set1<K>(1.98412698295895385996e-4);
  ps = ps * z + set1<K>(8.33333333332211858878e-3);
  ps = ps * z - set1<K>(1.66666666666666307295e-1);
  const D<K> sr = r + r * z * ps;
  D<K> pc = set1<K>(-1.13585365213876817300e-11) * z + set1<K>(2.08757008419747316778e-9);
  pc = pc * z - set1<K>(2.75573141792967388112e-7);
  pc = pc * z + set1<K>(2.48015872888517045348e-5);
  pc = pc * z - set1<K>(1.38888888888730564116e-3);
  pc = pc * z + set1<K>(4.16666666666665929218e-2);
  const D<K> cr = set1<K>(1.0) - set1<K>(0.5) * z + z * z * pc;
  // The quadrant k mod 4, exact for any k (k / 4 and its floor are exact), as static_cast<long long>(k) & 3
  // gives it; NaN and infinity convert to 0x80000000 and so give quadrant 0 as the scalar cast does.
  const I<K> q = toInt(k - set1<K>(4.0) * floor(k * set1<K>(0.25)));
  const I<K> one = set1i<K>(1), two = set1i<K>(2);
  const D<K> swap = asDouble(set1i<K>(0) - (q & one));
  const D<K> ssign = asDouble(shiftLeft<62>(q & two)), csign = asDouble(shiftLeft<62>((q + one) & two));
  s = blend(sr, cr, swap) ^ ssign;
  c = blend(cr, sr, swap) ^ csign;
}

/// fastSinCos(a[k], s[k], c[k]) for the 4 lanes.
SWARM_FORAGE_AVX2 inline void fastSinCos4(const __m256d& a, __m256d& s, __m256d& c) {
  lanes::D<1> a1, s1, c1;
  a1.v[0] = a;
  fastSinCosN<1>(a1, s1, c1);
  s = s1.v[0];
  c = c1.v[0];
}

/// out = fastAtan2(y[k], x[k]) for every lane (0 for (+-0, +-0), as the scalar one).
template <int K>
SWARM_FORAGE_LANES void fastAtan2N(const lanes::D<K>& y, const lanes::D<K>& x, lanes::D<K>& out) {
  using namespace lanes;
  constexpr double kPiHalf = 1.57079632679489661923, kPiQuarter = 0.78539816339744830962;
  const D<K> sign = set1<K>(-0.0), zero = set1<K>(0.0);
  const D<K> ax = andNot(sign, x), ay = andNot(sign, y);
  const D<K> both0 = cmp<_CMP_EQ_OQ>(ax, zero) & cmp<_CMP_EQ_OQ>(ay, zero);
  const D<K> swap = cmp<_CMP_GT_OQ>(ay, ax);
  const D<K> lo = blend(ay, ax, swap), hi = blend(ax, ay, swap);
  const D<K> mid = cmp<_CMP_GT_OQ>(lo, set1<K>(0.66) * hi);
  // One division: the scalar code's (lo - hi) / (lo + hi) or lo / hi, whichever the lane takes.
  const D<K> t = blend(lo, lo - hi, mid) / blend(hi, lo + hi, mid);
  const D<K> base = mid & set1<K>(kPiQuarter), more = mid & set1<K>(0.5 * 6.123233995736765886130e-17);
  const D<K> z = t * t;
  D<K> p = set1<K>(-8.750608600031904122785e-1) * z - set1<K>(1.615753718733365076637e1);
  p = p * z - set1<K>(7.500855792314704667340e1);
  p = p * z - set1<K>(1.228866684490136173410e2);
  p = p * z - set1<K>(6.485021904942025371773e1);
  D<K> q = z + set1<K>(2.485846490142306297962e1);
  q = q * z + set1<K>(1.650270098316988542046e2);
  q = q * z + set1<K>(4.328810604912902668951e2);
  q = q * z + set1<K>(4.853903996359136964868e2);
  q = q * z + set1<K>(1.945506571482613964425e2);
  D<K> a = t * z * p / q;
  a = base + (a + t + more);
  a = blend(a, set1<K>(kPiHalf) - a, swap);
  a = blend(a, set1<K>(2 * kPiHalf) - a, cmp<_CMP_LT_OQ>(x, zero));
  a = a ^ (y & sign);
  out = andNot(both0, a);  // +0 where both are zero
}

/// out = fastAtan2(y[k], x[k]) for the 4 lanes.
SWARM_FORAGE_AVX2 inline void fastAtan2_4(const __m256d& y, const __m256d& x, __m256d& out) {
  lanes::D<1> y1, x1, o;
  y1.v[0] = y;
  x1.v[0] = x;
  fastAtan2N<1>(y1, x1, o);
  out = o.v[0];
}

}  // namespace swarm_forage
