// FORDYCA 2019's light occlusion (docs/FIDELITY.md, "FORDYCA as it ran", (8)): whether a body cuts the ray
// from a robot to a nest light. Only the answer counts, never which body gave it or in which order the bodies
// were tested, so the search below may take any path that tests every body the exact test could accept.
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "swarm_forage/core/util/lanes_x4.hpp"
#include "swarm_forage/core/util/simd.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

namespace {
// The first and last set bits lo <= hi in [b0, b1]; false when none is.
inline bool setBitSpan(const uint64_t* bits, std::size_t b0, std::size_t b1, std::size_t& lo,
                       std::size_t& hi) {
  const std::size_t w0 = b0 / 64, w1 = b1 / 64;
  const uint64_t first = ~uint64_t{0} << (b0 % 64), last = ~uint64_t{0} >> (63 - b1 % 64);
  std::size_t w = w0;
  uint64_t m = bits[w] & first & (w == w1 ? last : ~uint64_t{0});
  while (!m) {
    if (++w > w1) return false;
    m = bits[w] & (w == w1 ? last : ~uint64_t{0});
  }
  lo = w * 64 + static_cast<std::size_t>(__builtin_ctzll(m));
  std::size_t v = w1;
  uint64_t n = bits[v] & last & (v == w0 ? first : ~uint64_t{0});
  while (!n) {  // ends at w at the latest
    --v;
    n = bits[v] & (v == w0 ? first : ~uint64_t{0});
  }
  hi = v * 64 + 63 - static_cast<std::size_t>(__builtin_clzll(n));
  return true;
}

// The stretch of a ray that a body can shadow, from the robot at (x, y) (slot self) along (dx, dy).
struct Stretch {
  double x, y, dx, dy, reach, pad;
  uint32_t self;
};

// The first slot in [k, e) but self whose body's centre lies within pad of the stretch (extended by pad):
// the bound that chooses which bodies get the exact test; e when none does.
inline uint32_t nextNear(const double* sx, const double* sy, const Stretch& s, uint32_t k, uint32_t e) {
  for (; k < e; ++k) {
    const double ox = sx[k] - s.x, oy = sy[k] - s.y, along = ox * s.dx + oy * s.dy;
    if (k != s.self && !(along < 0 || along > s.reach || std::abs(ox * s.dy - oy * s.dx) > s.pad)) return k;
  }
  return e;
}

// nextNear 4 slots at a time: a row's bodies are one range of slots, most often fewer than 4, so one step
// and one branch instead of one per body (the same comparisons on the same values).
SWARM_FORAGE_AVX2 uint32_t nextNearX4(const double* sx, const double* sy, const Stretch& s, uint32_t k,
                                      uint32_t e) {
  const __m256d x = _mm256_set1_pd(s.x), y = _mm256_set1_pd(s.y), dx = _mm256_set1_pd(s.dx),
                dy = _mm256_set1_pd(s.dy), reach = _mm256_set1_pd(s.reach), pad = _mm256_set1_pd(s.pad),
                zero = _mm256_setzero_pd(), sign = _mm256_set1_pd(-0.0);
  const __m256i self = _mm256_set1_epi64x(s.self), lane = _mm256_setr_epi64x(0, 1, 2, 3);
  for (; k < e; k += 4) {
    const __m256i slot = _mm256_add_epi64(_mm256_set1_epi64x(k), lane);
    const __m256i in =
        _mm256_andnot_si256(_mm256_cmpeq_epi64(slot, self), _mm256_cmpgt_epi64(_mm256_set1_epi64x(e), slot));
    const __m256d ox = _mm256_sub_pd(_mm256_maskload_pd(sx + k, in), x);
    const __m256d oy = _mm256_sub_pd(_mm256_maskload_pd(sy + k, in), y);
    const __m256d along = _mm256_add_pd(_mm256_mul_pd(ox, dx), _mm256_mul_pd(oy, dy));
    const __m256d off = _mm256_andnot_pd(sign, _mm256_sub_pd(_mm256_mul_pd(ox, dy), _mm256_mul_pd(oy, dx)));
    const __m256d near = _mm256_and_pd(
        _mm256_and_pd(_mm256_cmp_pd(along, zero, _CMP_GE_OQ), _mm256_cmp_pd(along, reach, _CMP_LE_OQ)),
        _mm256_cmp_pd(off, pad, _CMP_LE_OQ));
    const int hit = _mm256_movemask_pd(_mm256_and_pd(near, _mm256_castsi256_pd(in)));
    if (hit) return k + static_cast<uint32_t>(__builtin_ctz(static_cast<unsigned>(hit)));
  }
  return e;
}

// A margin over the ray's search region that covers the roundings of its bounds (positions are at most
// 10 km, so they round at about 1e-12 m).
constexpr double kSearchMargin = 1e-6;

// The part of a ray, from the robot, along which it is still below a body's height (shadowReach / d).
constexpr double shadowFraction(double lz) { return lz <= kFootBotHeight ? 1.0 : kFootBotHeight / lz; }
constexpr double kShadowFraction[3] = {shadowFraction(kFordycaLightHeight[0]),
                                       shadowFraction(kFordycaLightHeight[1]),
                                       shadowFraction(kFordycaLightHeight[2])};
static_assert(ArenaConfig::kLights == 3, "a fraction per light");
}  // namespace

void World::prepareShadows() {
  const std::size_t cells = static_cast<std::size_t>(grid_.columns()) * grid_.rows(), n = robots_.size();
  const std::size_t words = cells / 64 + 2;  // and a word for searchShadows' 8-byte loads at any byte
  // A small map is cleared whole; a large one (a sparse swarm in a big arena) bit by bit after the sensing.
  if (shadow_bits_.size() != words) shadow_bits_.assign(words, 0);
  if (words <= n) std::memset(shadow_bits_.data(), 0, words * sizeof(uint64_t));
  shadow_inv_cell_ = 1.0 / grid_.cellSize();
  uint64_t* const bits = shadow_bits_.data();
  // Which slots trace, set here by id: the sensing then reads a byte in slot order instead of a carried
  // block by id. Every slot is written (rank is a permutation), without a branch on the carriers.
  const bool all = !config_.light_only_carrying;
  traced_.resize(n);
  uint8_t* const traced = traced_.data();
  const uint32_t* const rank = grid_.rank().data();
  const int32_t* const carried = robots_.carried.data();
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t c = grid_.cellOf(static_cast<uint32_t>(i));
    if (c != UniformGrid::kNowhere) bits[c / 64] |= uint64_t{1} << (c % 64);
    traced[rank[i]] = static_cast<uint8_t>(all | (carried[i] >= 0));
  }
}

void World::clearShadowCells() {
  const std::size_t n = robots_.size();
  if (shadow_bits_.size() <= n) return;  // prepareShadows clears it whole
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t c = grid_.cellOf(static_cast<uint32_t>(i));
    if (c != UniformGrid::kNowhere) shadow_bits_[c / 64] = 0;
  }
}

// The lights in `search` (a mask) that a body shadows from the robot in `self`, each by a search of its
// own (one walk over the hull of the three rays' cells tested every body against every ray left: more
// branches, more mispredicted).
unsigned World::searchShadows(uint32_t self, unsigned search, const double* d, const double* ux,
                              const double* uy) const {
  const double x = sx_[self], y = sy_[self];
  const double r = config_.robot.radius;
  const uint32_t* const order = grid_.order().data();
  uint32_t* const witness = &shadow_witness_[static_cast<std::size_t>(order[self]) * ArenaConfig::kLights];
  const double cell = grid_.cellSize(), inv_cell = shadow_inv_cell_;
  const int nx = grid_.columns(), ny = grid_.rows();
  const auto cellIn = [inv_cell](double v, int n) {
    return std::clamp(static_cast<int>(v * inv_cell), 0, n - 1);
  };
  const uint64_t* const bits = shadow_bits_.data();
  const bool x4 = simdEnabled();
  unsigned found = 0;
  for (unsigned left = search; left; left &= left - 1) {
    const int l = __builtin_ctz(left);
    const double lx = lights_[l].x(), ly = lights_[l].y(), lz = kFordycaLightHeight[l], dx = ux[l],
                 dy = uy[l];
    // Only a body entered within shadowReach of the robot (seen from above) is low enough to cut the ray:
    // a body whose centre lies within pad (its disc and its gripper) of that stretch of the ray's ground
    // projection, extended by pad. The bound (nextNear) only chooses which bodies get the exact test; pad's
    // 1e-9 covers its roundings (and those of reach, a product for shadowReach's quotient).
    const double pad = r + kGripperRadius + 1e-9, reach = kShadowFraction[l] * d[l] + pad;
    const Stretch stretch{x, y, dx, dy, reach, pad, self};
    const auto next = [&](uint32_t k, uint32_t e) {
      return x4 ? nextNearX4(sx_.data(), sy_.data(), stretch, k, e)
                : nextNear(sx_.data(), sy_.data(), stretch, k, e);
    };
    uint32_t hit = kNoWitness;
    // The cells of grid_ within m of the segment from the robot along the ray for `reach`, row by row from
    // the robot's row outward: in a crowd a body near the robot shadows it, and the search ends there. A
    // row's cells from its first occupied one to its last (a bit each in shadow_bits_) hold one range of
    // slots, as the grid sorts bodies row-major; their bodies are bounded 4 at a time (nextNearX4). The
    // bounds are rounded a little differently from the grid's cells (a product for a quotient); the margin
    // covers that too.
    const double m = pad + kSearchMargin;
    const double qy = y + reach * dy;
    const int row0 = cellIn(std::min(y, qy) - m, ny), row1 = cellIn(std::max(y, qy) + m, ny);
    const bool up = dy >= 0, right = dx >= 0;
    // Row i (from the robot's) holds the part of the segment whose height lies within m of it: t in
    // [t_near + i step, t_near + i step + span] (all of it when the ray runs along the rows).
    double t_near = 0, step = 0, span = reach;
    if (std::abs(dy) >= 1e-9) {
      const double inv = 1.0 / std::abs(dy);
      step = cell * inv;
      span = step + 2 * m * inv;
      t_near = (up ? row0 * cell - m - y : y - (row1 + 1) * cell - m) * inv;
    }
    for (int i = 0, rows = row1 - row0 + 1; i < rows; ++i) {
      const double ta = t_near + i * step, t0 = std::max(0.0, ta), t1 = std::min(reach, ta + span);
      if (t0 > t1) continue;
      const double xa = x + t0 * dx, xb = x + t1 * dx;  // xa <= xb when right
      const int c0 = cellIn((right ? xa : xb) - m, nx), c1 = cellIn((right ? xb : xa) + m, nx);
      const std::size_t base = static_cast<std::size_t>(up ? row0 + i : row1 - i) * nx;
      // The row's occupied cells from the first to the last: one range of slots (sorted row-major).
      std::size_t lo, hi;
      if (c1 - c0 <= 56) {  // one 8-byte load from the first cell's byte holds them all: no loop over words
        const std::size_t b0 = base + c0;
        uint64_t occupied;
        std::memcpy(&occupied, reinterpret_cast<const uint8_t*>(bits) + b0 / 8, sizeof occupied);
        occupied = occupied >> (b0 % 8) & (~uint64_t{0} >> (63 - (c1 - c0)));
        if (!occupied) continue;
        lo = b0 + static_cast<std::size_t>(__builtin_ctzll(occupied));
        hi = b0 + 63 - static_cast<std::size_t>(__builtin_clzll(occupied));
      } else if (!setBitSpan(bits, base + c0, base + c1, lo, hi)) {
        continue;
      }
      const uint32_t e = grid_.cellRun(hi).end;
      for (uint32_t k = next(grid_.cellRun(lo).begin, e); k < e; k = next(k + 1, e))
        if (footBotShadows(x, y, lx, ly, lz, sx_[k], sy_[k], sth_[k], r)) {
          hit = k;
          break;
        }
      if (hit != kNoWitness) break;
    }
    witness[l] = hit == kNoWitness ? kNoWitness : order[hit];
    found |= (hit != kNoWitness ? 1u : 0u) << l;
  }
  return found;
}

void World::shadowedLights(uint32_t slot, double& light_x, double& light_y, uint8_t& shadowed) const {
  const double x = sx_[slot], y = sy_[slot];
  const double r = config_.robot.radius;
  const uint32_t* const rank = grid_.rank().data();
  const uint32_t placed = grid_.placed();
  const uint32_t* const witness =
      &shadow_witness_[static_cast<std::size_t>(grid_.order()[slot]) * ArenaConfig::kLights];
  // A light's direction is also its ray's.
  double d[ArenaConfig::kLights], ux[ArenaConfig::kLights], uy[ArenaConfig::kLights];
  unsigned skip = 0, search = 0;
  for (int l = 0; l < ArenaConfig::kLights; ++l) {
    const double lx = lights_[l].x(), ly = lights_[l].y(), dx = lx - x, dy = ly - y;
    d[l] = std::sqrt(dx * dx + dy * dy);
    ux[l] = uy[l] = 0;
    if (d[l] < 1e-12) continue;  // at the light: not shadowed, and no direction to it
    const double inv = 1.0 / d[l];
    ux[l] = dx * inv;
    uy[l] = dy * inv;
    // The body that shadowed this light last tick most often still does (bodies move little in a tick):
    // one exact test instead of a search. It changes no result, only how soon it is found.
    const uint32_t w = witness[l];
    if (w != kNoWitness) {
      const uint32_t k = rank[w];
      if (k < placed && k != slot &&
          footBotShadows(x, y, lx, ly, kFordycaLightHeight[l], sx_[k], sy_[k], sth_[k], r)) {
        skip |= 1u << l;
        continue;
      }
    }
    search |= 1u << l;
  }
  if (search) skip |= searchShadows(slot, search, d, ux, uy);
  // The sum of unit vectors to the lights not shadowed, as lightSum (world_sensing.cpp) adds them. A light
  // left out adds +0, which changes no sum (none is -0: nor is a difference of equal values); adding a
  // select measured faster than an `if` around the sums (docs/performance.md).
  double sum_x = 0, sum_y = 0;
  for (int l = 0; l < ArenaConfig::kLights; ++l) {
    const bool lit = (d[l] > 1e-9) & !(skip >> l & 1);
    sum_x += lit ? ux[l] : 0.0;
    sum_y += lit ? uy[l] : 0.0;
  }
  shadowed = static_cast<uint8_t>(skip);
  light_x = sum_x;
  light_y = sum_y;
}

}  // namespace swarm_forage
