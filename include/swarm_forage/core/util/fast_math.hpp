#pragma once
// Inline sine/cosine and atan2 for the per-robot hot loops (libm's are out-of-line calls that cost more
// than the rest of a robot's tick). Cephes' polynomials: within 1-2 ulp of libm for the angles robots
// see; deterministic, as they use only +, *, / and sqrt-free arithmetic.
#include <cmath>
#include <cstdint>
#include <cstring>

namespace swarm_forage {

/// sin(a) and cos(a) for |a| up to ~1e6 rad.
inline void fastSinCos(double a, double& s, double& c) {
  // a = k pi/2 + r, |r| <= pi/4 (Cody-Waite: pi/2 in three parts).
  const double k = std::floor(a * 0.63661977236758134308 + 0.5);
  const double r =
      ((a - k * 1.57079625129699707031) - k * 7.54978941586159635336e-8) - k * 5.39030285815811905290e-15;
  const double z = r * r;
  const double sr =
      r +
      r * z *
          (((((1.58962301576546568060e-10 * z - 2.50507477628578072866e-8) * z + 2.75573136213857245213e-6) *
                 z -
             1.98412698295895385996e-4) *
                z +
            8.33333333332211858878e-3) *
               z -
           1.66666666666666307295e-1);
  const double cr =
      1.0 - 0.5 * z +
      z * z *
          (((((-1.13585365213876817300e-11 * z + 2.08757008419747316778e-9) * z - 2.75573141792967388112e-7) *
                 z +
             2.48015872888517045348e-5) *
                z -
            1.38888888888730564116e-3) *
               z +
           4.16666666666665929218e-2);
  // The quadrant by bit operations, not a switch: headings are random, and a mispredicted branch cost as
  // much as the polynomials (17 against 8 ns a call for random angles). Odd quadrants swap sine and
  // cosine; quadrants 2 and 3 negate the sine, 1 and 2 the cosine (a sign flip, as unary minus).
  const auto q = static_cast<uint64_t>(static_cast<long long>(k)) & 3;
  uint64_t bs, bc;
  std::memcpy(&bs, &sr, sizeof bs);
  std::memcpy(&bc, &cr, sizeof bc);
  const uint64_t swap = 0 - (q & 1);
  const uint64_t so = ((bc & swap) | (bs & ~swap)) ^ ((q & 2) << 62);
  const uint64_t co = ((bs & swap) | (bc & ~swap)) ^ (((q + 1) & 2) << 62);
  std::memcpy(&s, &so, sizeof s);
  std::memcpy(&c, &co, sizeof c);
}

/// atan2(y, x) in [-pi, pi]; 0 for (0, 0).
inline double fastAtan2(double y, double x) {
  constexpr double kPiHalf = 1.57079632679489661923, kPiQuarter = 0.78539816339744830962;
  const double ax = std::fabs(x), ay = std::fabs(y);
  if (ax == 0 && ay == 0) return 0.0;
  // atan(t) for t = min/max in [0, 1]: reduce to |t| <= tan(pi/8) where needed (Cephes atan). Selects and
  // a sign bit instead of branches: steering forces point either side of the heading at random (the
  // same bits; 11-12 against 7.5 ns a call for such forces).
  const bool swap = ay > ax;
  const double lo = swap ? ax : ay, hi = swap ? ay : ax;
  const bool mid = lo > 0.66 * hi;  // atan(r) = pi/4 + atan((r - 1) / (r + 1)), one division
  const double t = mid ? (lo - hi) / (lo + hi) : lo / hi;
  const double base = mid ? kPiQuarter : 0.0, more = mid ? 0.5 * 6.123233995736765886130e-17 : 0.0;
  const double z = t * t;
  const double p =
      (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z - 7.500855792314704667340e1) * z -
       1.228866684490136173410e2) *
          z -
      6.485021904942025371773e1;
  const double q =
      ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z + 4.328810604912902668951e2) *
           z +
       4.853903996359136964868e2) *
          z +
      1.945506571482613964425e2;
  double a = base + (t * z * p / q + t + more);  // atan(min/max) in [0, pi/4]
  a = swap ? kPiHalf - a : a;
  a = x < 0 ? 2 * kPiHalf - a : a;
  uint64_t ba, by;  // the sign of y (a >= 0 here): what signbit(y) ? -a : a gives
  std::memcpy(&ba, &a, sizeof ba);
  std::memcpy(&by, &y, sizeof by);
  ba ^= by & 0x8000000000000000ULL;
  std::memcpy(&a, &ba, sizeof a);
  return a;
}

}  // namespace swarm_forage
