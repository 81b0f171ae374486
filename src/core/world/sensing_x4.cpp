// World::senseRobot's 4-lane path (sense() takes it when simdEnabled()): the neighbour scan 4 slots at a
// time, the proximity rays 4 at a time, the light vectors of 4 robots at a time. The kernels are compiled
// for AVX2 per function, never with FMA, and do the scalar path's IEEE operations on the same operands:
// every reading has the same bits (test_sensing.cpp checks it).
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "swarm_forage/core/util/fast_math_x4.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

namespace {

// For each 4-bit lane mask, the 32-bit lanes that move the selected doubles to the front, in order.
struct Compaction {
  int32_t idx[16][8];
  constexpr Compaction() : idx{} {
    for (int m = 0; m < 16; ++m) {
      int o = 0;
      for (int l = 0; l < 4; ++l)
        if ((m >> l) & 1) {
          idx[m][2 * o] = 2 * l;
          idx[m][2 * o + 1] = 2 * l + 1;
          ++o;
        }
    }
  }
};
constexpr Compaction kCompaction;

// What one robot's scan and rays need: plain data, as the AVX2 kernels are free functions (the target
// attribute stays off World's members and off anything inline the rest of the library shares).
struct Probe {
  const double *px, *py;                      // slots' positions
  const std::pair<uint32_t, uint32_t>* runs;  // slot runs around the robot (its own slot among them)
  std::size_t n_runs;
  long long self;  // the robot's slot
  double x, y, hx, hy, reach2;
  double *near_x, *near_y, *near_d2;  // room for every slot of the runs, and 4 more
  const double *ray_x, *ray_y;        // padded to a multiple of 4
  std::size_t n_rays;
  bool near_wall;
  double W, H, s0, s1, r2;
};

SWARM_FORAGE_AVX2 inline __m256i firstLanes(std::size_t n) {  // lanes [0, n) set
  return _mm256_cmpgt_epi64(_mm256_set1_epi64x(static_cast<long long>(n)), _mm256_setr_epi64x(0, 1, 2, 3));
}

SWARM_FORAGE_AVX2 inline void appendLanes(double* out, std::size_t at, __m256d v, __m256i perm) {
  _mm256_storeu_pd(out + at, _mm256_castsi256_pd(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(v), perm)));
}

// The scan: nearest2 the least squared distance, near_* the bodies within reach in the robot frame (in
// scan order); returns how many. Without branches on the data: the lanes past a run's end and the robot's
// own slot are masked, and the compaction stores every time (advancing by the lanes kept), as those
// branches were mispredicted. std::min(a, b) is (b < a) ? b : a and _mm256_min_pd(p, q) is
// (p < q) ? p : q, hence the swapped operands here and below.
SWARM_FORAGE_AVX2 std::size_t scanX4(const Probe& p, double& nearest2) {
  const __m256d x = _mm256_set1_pd(p.x), y = _mm256_set1_pd(p.y), hx = _mm256_set1_pd(p.hx),
                hy = _mm256_set1_pd(p.hy), nhy = _mm256_set1_pd(-p.hy), reach2 = _mm256_set1_pd(p.reach2),
                none = _mm256_set1_pd(1e300);
  const __m256i self = _mm256_set1_epi64x(p.self), lane = _mm256_setr_epi64x(0, 1, 2, 3);
  __m256d nearest = none;
  std::size_t n = 0;
  for (std::size_t r = 0; r < p.n_runs; ++r) {
    for (uint32_t k = p.runs[r].first, e = p.runs[r].second; k < e; k += 4) {
      const __m256i slot = _mm256_add_epi64(_mm256_set1_epi64x(k), lane);
      const __m256i m = _mm256_andnot_si256(_mm256_cmpeq_epi64(slot, self), firstLanes(e - k));
      const __m256d dx = _mm256_sub_pd(_mm256_maskload_pd(p.px + k, m), x);
      const __m256d dy = _mm256_sub_pd(_mm256_maskload_pd(p.py + k, m), y);
      const __m256d d2 = _mm256_blendv_pd(none, _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                                          _mm256_castsi256_pd(m));
      nearest = _mm256_min_pd(d2, nearest);
      const int in = _mm256_movemask_pd(_mm256_cmp_pd(d2, reach2, _CMP_LT_OQ));  // never a masked lane
      const __m256i perm = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kCompaction.idx[in]));
      appendLanes(p.near_x, n, _mm256_add_pd(_mm256_mul_pd(hx, dx), _mm256_mul_pd(hy, dy)), perm);
      appendLanes(p.near_y, n, _mm256_add_pd(_mm256_mul_pd(nhy, dx), _mm256_mul_pd(hx, dy)), perm);
      appendLanes(p.near_d2, n, d2, perm);
      n += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(in)));
    }
  }
  alignas(32) double least[4];
  _mm256_store_pd(least, nearest);
  // No NaN and no -0 among them: any order gives the scalar path's least value.
  nearest2 = std::min(std::min(least[0], least[1]), std::min(least[2], least[3]));
  return n;
}

// The first ray, in sensor order, that meets a wall or body within the threat distance, and the distance
// `hit` along it; -1 when none. Per ray the scalar path keeps max(entry, s0) of the least entry met
// (wall or bodies, in any order: the same value), so the lanes take the least entry, then the max.
SWARM_FORAGE_AVX2 int firstRayX4(const Probe& p, std::size_t n_near, double& hit) {
  const __m256d zero = _mm256_setzero_pd(), inf = _mm256_set1_pd(std::numeric_limits<double>::infinity()),
                s1 = _mm256_set1_pd(p.s1), r2 = _mm256_set1_pd(p.r2), hx = _mm256_set1_pd(p.hx),
                hy = _mm256_set1_pd(p.hy), x = _mm256_set1_pd(p.x), y = _mm256_set1_pd(p.y),
                wx = _mm256_set1_pd(p.W - p.x), wy = _mm256_set1_pd(p.H - p.y), far = _mm256_set1_pd(1e9),
                sign = _mm256_set1_pd(-0.0);
  for (std::size_t g = 0; g < p.n_rays; g += 4) {
    const __m256d rx = _mm256_loadu_pd(p.ray_x + g), ry = _mm256_loadu_pd(p.ray_y + g);
    __m256d best = inf;
    if (p.near_wall) {
      const __m256d ux = _mm256_sub_pd(_mm256_mul_pd(hx, rx), _mm256_mul_pd(hy, ry));
      const __m256d uy = _mm256_add_pd(_mm256_mul_pd(hy, rx), _mm256_mul_pd(hx, ry));
      // ux < 0 ? x / -ux : ux > 0 ? (W - x) / ux : 1e9, and so for y
      __m256d tx = _mm256_blendv_pd(far, _mm256_div_pd(wx, ux), _mm256_cmp_pd(ux, zero, _CMP_GT_OQ));
      tx = _mm256_blendv_pd(tx, _mm256_div_pd(x, _mm256_xor_pd(ux, sign)),
                            _mm256_cmp_pd(ux, zero, _CMP_LT_OQ));
      __m256d ty = _mm256_blendv_pd(far, _mm256_div_pd(wy, uy), _mm256_cmp_pd(uy, zero, _CMP_GT_OQ));
      ty = _mm256_blendv_pd(ty, _mm256_div_pd(y, _mm256_xor_pd(uy, sign)),
                            _mm256_cmp_pd(uy, zero, _CMP_LT_OQ));
      const __m256d t = _mm256_min_pd(ty, tx);  // std::min(tx, ty)
      best = _mm256_blendv_pd(inf, t, _mm256_cmp_pd(t, s1, _CMP_LE_OQ));
    }
    for (std::size_t i = 0; i < n_near; ++i) {
      const __m256d along = _mm256_add_pd(_mm256_mul_pd(_mm256_broadcast_sd(p.near_x + i), rx),
                                          _mm256_mul_pd(_mm256_broadcast_sd(p.near_y + i), ry));
      const __m256d q2 = _mm256_sub_pd(_mm256_broadcast_sd(p.near_d2 + i), _mm256_mul_pd(along, along));
      const __m256d through =
          _mm256_and_pd(_mm256_cmp_pd(along, zero, _CMP_GT_OQ), _mm256_cmp_pd(q2, r2, _CMP_LT_OQ));
      if (_mm256_testz_pd(through, through)) continue;  // in no lane: no square root
      const __m256d entry = _mm256_sub_pd(along, _mm256_sqrt_pd(_mm256_sub_pd(r2, q2)));
      const __m256d in = _mm256_and_pd(through, _mm256_cmp_pd(entry, s1, _CMP_LE_OQ));
      best = _mm256_min_pd(_mm256_blendv_pd(inf, entry, in), best);
    }
    const std::size_t valid = std::min<std::size_t>(4, p.n_rays - g);
    const int lanes = _mm256_movemask_pd(_mm256_cmp_pd(best, s1, _CMP_LE_OQ)) & ((1 << valid) - 1);
    if (lanes) {
      const int lane = __builtin_ctz(static_cast<unsigned>(lanes));
      alignas(32) double b[4];
      _mm256_store_pd(b, best);
      hit = std::max(b[lane], p.s0);
      return static_cast<int>(g) + lane;
    }
  }
  return -1;
}

// For the n <= 4 robots at slots xs, ys, ths: the heading's cosine and sine (fastSinCos) and, with
// `lights`, the light vector in the map frame (World::lightVector without occlusion).
SWARM_FORAGE_AVX2 void headingsX4(const double* xs, const double* ys, const double* ths, std::size_t n,
                                  const Vec2* lights, double* hx, double* hy, double* lx, double* ly) {
  const __m256i m = firstLanes(n);
  __m256d s, c;
  fastSinCos4(_mm256_maskload_pd(ths, m), s, c);
  _mm256_storeu_pd(hx, c);
  _mm256_storeu_pd(hy, s);
  if (!lights) return;
  const __m256d x = _mm256_maskload_pd(xs, m), y = _mm256_maskload_pd(ys, m), tiny = _mm256_set1_pd(1e-9),
                one = _mm256_set1_pd(1.0);
  __m256d ax = _mm256_setzero_pd(), ay = _mm256_setzero_pd();
  for (int l = 0; l < ArenaConfig::kLights; ++l) {
    const __m256d dx = _mm256_sub_pd(_mm256_set1_pd(lights[l].x()), x);
    const __m256d dy = _mm256_sub_pd(_mm256_set1_pd(lights[l].y()), y);
    const __m256d len = _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)));
    const __m256d on = _mm256_cmp_pd(len, tiny, _CMP_GT_OQ), inv = _mm256_div_pd(one, len);
    ax = _mm256_blendv_pd(ax, _mm256_add_pd(ax, _mm256_mul_pd(dx, inv)), on);
    ay = _mm256_blendv_pd(ay, _mm256_add_pd(ay, _mm256_mul_pd(dy, inv)), on);
  }
  _mm256_storeu_pd(lx, ax);
  _mm256_storeu_pd(ly, ay);
}

}  // namespace

void World::senseSlotsX4(std::size_t first, std::size_t end, WorkerScratch& scratch) {
  const RobotConfig& rc = config_.robot;
  const double W = config_.arena.width, H = config_.arena.height;
  const double reach = 2 * rc.radius + rc.threat_distance;
  const bool occlusion = config_.quirks.has(Quirk::kLightOcclusion);
  Probe p{};
  p.px = sx_.data();
  p.py = sy_.data();
  p.reach2 = reach * reach;
  p.ray_x = ray_x_.data();
  p.ray_y = ray_y_.data();
  p.n_rays = rays_.size();
  p.W = W;
  p.H = H;
  p.s0 = rc.radius;
  p.s1 = rc.radius + rc.threat_distance;
  p.r2 = rc.radius * rc.radius;
  auto& runs = scratch.runs;
  double hx4[4] = {}, hy4[4] = {}, lx4[4] = {}, ly4[4] = {};
  for (std::size_t s = first; s < end; ++s) {
    const auto self = static_cast<uint32_t>(s);
    const double x = sx_[s], y = sy_[s];
    const std::size_t lane = (s - first) % 4;
    if (lane == 0)
      headingsX4(sx_.data() + s, sy_.data() + s, sth_.data() + s, std::min<std::size_t>(4, end - s),
                 occlusion ? nullptr : lights_, hx4, hy4, lx4, ly4);
    const double hx = hx4[lane], hy = hy4[lane];
    runs.clear();
    std::size_t total = 0;
    grid_.forNeighbourRuns(x, y, [&](uint32_t b, uint32_t e) {
      runs.emplace_back(b, e);
      total += e - b;
    });
    if (scratch.near_x.size() < total + 4) {
      scratch.near_x.resize(2 * total + 4);
      scratch.near_y.resize(2 * total + 4);
      scratch.near_d2.resize(2 * total + 4);
    }
    p.self = self;
    p.runs = runs.data();
    p.n_runs = runs.size();
    p.x = x;
    p.y = y;
    p.hx = hx;
    p.hy = hy;
    p.near_x = scratch.near_x.data();
    p.near_y = scratch.near_y.data();
    p.near_d2 = scratch.near_d2.data();
    double nearest2;
    const std::size_t n_near = scanX4(p, nearest2);
    nearest2_[s] = nearest2;
    p.near_wall = x < reach || y < reach || x > W - reach || y > H - reach;
    double best_x = 0, best_y = 0;
    bool threat = false;
    if (n_near || p.near_wall) {
      double hit;
      const int ray = firstRayX4(p, n_near, hit);
      if (ray >= 0) {
        best_x = hit * rays_[ray].x();
        best_y = hit * rays_[ray].y();
        threat = true;
      }
    }
    double lx, ly;
    uint8_t shadowed = 0;
    if (occlusion) {
      lightVector(self, lx, ly, shadowed);
    } else {
      lx = lx4[lane];
      ly = ly4[lane];
    }
    storeReading(self, hx, hy, threat, best_x, best_y, lx, ly, shadowed);
  }
}

}  // namespace swarm_forage
