// World::senseRobot's 4-lane path (sense() takes it when simdEnabled()): the neighbour scan 4 slots at a
// time, the proximity rays 4 at a time. The kernels are compiled
// for AVX2 per function, never with FMA, and do the scalar path's IEEE operations on the same operands:
// every reading has the same bits (test_sensing.cpp checks it).
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "swarm_forage/core/util/fast_math.hpp"
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

// What the kernel needs: plain data, as the AVX2 kernels are free functions (the target attribute stays
// off World's members and off anything inline the rest of the library shares).
struct Probe {
  const double *px, *py, *pth;  // slots' poses
  const UniformGrid* grid;
  const double *ray_x, *ray_y;  // padded to a multiple of 4
  std::size_t n_rays;
  std::size_t left_rays;              // the rays of the leading groups of 4 that all point left (y > 0)
  double *near_x, *near_y, *near_d2;  // room for the placed bodies, kMaxPending more and 4 more
  double reach, reach2, W, H, s0, s1, r2, cell;
  double right_of;  // a body's centre below this y in the robot frame is right of every left ray's reach
  int cols, rows;
  bool all_headings;  // every robot's heading (light_occlusion: its lights turn by it), else the pending's
};

// Results by slot of a block of slots (the 4-lane heading stores write whole groups of 4).
constexpr std::size_t kBlock = 64;
struct BlockOut {
  double hx[kBlock], hy[kBlock], ox[kBlock], oy[kBlock];
  bool threat[kBlock];
};

SWARM_FORAGE_AVX2 inline __m256i firstLanes(std::size_t n) {  // lanes [0, n) set
  return _mm256_cmpgt_epi64(_mm256_set1_epi64x(static_cast<long long>(n)), _mm256_setr_epi64x(0, 1, 2, 3));
}

SWARM_FORAGE_AVX2 inline void appendLanes(double* out, std::size_t at, __m256d v, __m256i perm) {
  _mm256_storeu_pd(out + at, _mm256_castsi256_pd(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(v), perm)));
}

// One robot's scan state: the least squared distance so far (per lane) and the bodies kept.
struct Scan {
  __m256d x, y, nearest;
  __m256i self;
  std::size_t n;
  double *near_x, *near_y;  // Probe's, held here: a store through Probe's would reload them
};

// The scan of 4 slots from k, lanes [0, e - k) of them but the robot's own: nearest the least squared
// distance, near_x and near_y the (dx, dy) of the bodies within reach, in scan order (castPending turns
// them into the robot frame and their d2: most steps keep none). The lanes past a run's end and the
// robot's own slot are masked. The compaction (2 permutes and stores, advancing by the lanes kept) runs
// at every step where many steps keep a body (1 in 10 in 96x48 at N = 16,384: a branch on it was
// mispredicted, and the rays read the stores only after the block's scans); kSparse, where few do (1 in 20
// in 64x32 at N = 4,096), only for a step that keeps one (the branch predicted, the stores saved).
// std::min(a, b) is (b < a) ? b : a and _mm256_min_pd(p, q) is (p < q) ? p : q, hence the swapped operands
// here and below.
template <bool kSparse>
SWARM_FORAGE_AVX2 inline void scanStep(const Probe& p, Scan& s, uint32_t k, uint32_t e) {
  const __m256d reach2 = _mm256_set1_pd(p.reach2), none = _mm256_set1_pd(1e300);
  const __m256i slot = _mm256_add_epi64(_mm256_set1_epi64x(k), _mm256_setr_epi64x(0, 1, 2, 3));
  const __m256i m = _mm256_andnot_si256(_mm256_cmpeq_epi64(slot, s.self), firstLanes(e - k));
  const __m256d dx = _mm256_sub_pd(_mm256_maskload_pd(p.px + k, m), s.x);
  const __m256d dy = _mm256_sub_pd(_mm256_maskload_pd(p.py + k, m), s.y);
  const __m256d d2 = _mm256_blendv_pd(none, _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                                      _mm256_castsi256_pd(m));
  s.nearest = _mm256_min_pd(d2, s.nearest);
  const int in = _mm256_movemask_pd(_mm256_cmp_pd(d2, reach2, _CMP_LT_OQ));  // never a masked lane
  if (kSparse && !in) return;
  const __m256i perm = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kCompaction.idx[in]));
  appendLanes(s.near_x, s.n, dx, perm);
  appendLanes(s.near_y, s.n, dy, perm);
  s.n += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(in)));
}

// The first ray from ray `from` on (a multiple of 4), in sensor order, that meets a wall or body within the
// threat distance, and the distance `hit` along it; -1 when none; the bodies are near_*[at, at + n_near). Per
// ray the scalar path keeps max(entry, s0) of the least entry met (wall or bodies, in any order: the same
// value), so the lanes take the least entry, then the max.
SWARM_FORAGE_AVX2 int firstRayX4(const Probe& p, double px, double py, double phx, double phy, bool near_wall,
                                 std::size_t at, std::size_t n_near, std::size_t from, double& hit) {
  const __m256d zero = _mm256_setzero_pd(), inf = _mm256_set1_pd(std::numeric_limits<double>::infinity()),
                s1 = _mm256_set1_pd(p.s1), r2 = _mm256_set1_pd(p.r2), hx = _mm256_set1_pd(phx),
                hy = _mm256_set1_pd(phy), x = _mm256_set1_pd(px), y = _mm256_set1_pd(py),
                wx = _mm256_set1_pd(p.W - px), wy = _mm256_set1_pd(p.H - py), far = _mm256_set1_pd(1e9),
                sign = _mm256_set1_pd(-0.0);
  for (std::size_t g = from; g < p.n_rays; g += 4) {
    const __m256d rx = _mm256_loadu_pd(p.ray_x + g), ry = _mm256_loadu_pd(p.ray_y + g);
    __m256d best = inf;
    if (near_wall) {
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
    for (std::size_t i = at; i < at + n_near; ++i) {
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

// For the n <= 4 robots at slots xs, ys, ths: the grid cell (UniformGrid::cellX, cellY) and, with
// p.all_headings, the heading's cosine and sine (fastSinCos).
SWARM_FORAGE_AVX2 void cellsAndHeadingsX4(const Probe& p, std::size_t first, std::size_t n, double* hx,
                                          double* hy, int* cx, int* cy) {
  const __m256i m = firstLanes(n);
  if (p.all_headings) {
    __m256d s, c;
    fastSinCos4(_mm256_maskload_pd(p.pth + first, m), s, c);
    _mm256_storeu_pd(hx, c);
    _mm256_storeu_pd(hy, s);
  }
  const __m256d x = _mm256_maskload_pd(p.px + first, m), y = _mm256_maskload_pd(p.py + first, m),
                cell = _mm256_set1_pd(p.cell);
  // std::clamp(static_cast<int>(x / cell), 0, cols - 1); positions are never NaN
  const __m128i zero = _mm_setzero_si128();
  _mm_storeu_si128(
      reinterpret_cast<__m128i*>(cx),
      _mm_max_epi32(_mm_min_epi32(_mm256_cvttpd_epi32(_mm256_div_pd(x, cell)), _mm_set1_epi32(p.cols - 1)),
                    zero));
  _mm_storeu_si128(
      reinterpret_cast<__m128i*>(cy),
      _mm_max_epi32(_mm_min_epi32(_mm256_cvttpd_epi32(_mm256_div_pd(y, cell)), _mm_set1_epi32(p.rows - 1)),
                    zero));
}

// The robots of a block with a body or a wall in reach, whose rays are still to cast: their bodies are
// near_*[at, at + n). Cast once more than kMaxPending bodies are kept (a block keeps ~20).
constexpr std::size_t kMaxPending = 4 * kBlock;
struct Pending {
  uint32_t at[kBlock], n[kBlock];
  uint8_t slot[kBlock], wall[kBlock];
  std::size_t count = 0, used = 0;  // robots, and bodies kept in near_*
};

// The rays of the pending robots, one after the other (a quarter of the robots, those with a body near:
// a branch per robot on it mispredicted, and cost the scans after it).
SWARM_FORAGE_AVX2 void castPending(const Probe& p, std::size_t first, Pending& q, BlockOut& o) {
  if (!p.all_headings)  // only these robots turn what they see into their frame: their headings, 4 at a time
    for (std::size_t k = 0; k < q.count; k += 4) {
      alignas(32) double th[4] = {0, 0, 0, 0}, s[4], c[4];
      const std::size_t lanes = std::min<std::size_t>(4, q.count - k);
      for (std::size_t j = 0; j < lanes; ++j) th[j] = p.pth[first + q.slot[k + j]];
      __m256d vs, vc;
      fastSinCos4(_mm256_load_pd(th), vs, vc);
      _mm256_store_pd(s, vs);
      _mm256_store_pd(c, vc);
      for (std::size_t j = 0; j < lanes; ++j) {
        o.hx[q.slot[k + j]] = c[j];
        o.hy[q.slot[k + j]] = s[j];
      }
    }
  for (std::size_t k = 0; k < q.count; ++k) {
    const std::size_t i = q.slot[k], s = first + i;
    const double hx = o.hx[i], hy = o.hy[i];
    bool right = !q.wall[k];
    for (std::size_t j = q.at[k]; j < q.at[k] + q.n[k]; ++j) {  // (dx, dy) into the robot frame
      const double dx = p.near_x[j], dy = p.near_y[j];
      p.near_x[j] = hx * dx + hy * dy;
      p.near_y[j] = -hy * dx + hx * dy;
      p.near_d2[j] = dx * dx + dy * dy;  // the scan's d2
      right &= p.near_y[j] < p.right_of;
    }
    // Bodies all well right of the robot: a ray pointing left passes at more than the radius from each
    // (its point nearest the centre lies left of the robot), so the left rays' groups cannot hit.
    double hit;
    const int ray =
        firstRayX4(p, p.px[s], p.py[s], hx, hy, q.wall[k], q.at[k], q.n[k], right ? p.left_rays : 0, hit);
    if (ray >= 0) {  // the reading in the robot frame: the ray itself, scaled
      o.ox[i] = hit * p.ray_x[ray];
      o.oy[i] = hit * p.ray_y[ray];
      o.threat[i] = true;
    }
  }
  q.count = q.used = 0;
}

// World::senseRobot for the slots [first, first + count), count <= kBlock: headings, cells and lights 4
// robots at a time and every robot's neighbour runs, then each robot's scan 4 slots at a time (one step
// per run of slots: runs are short, a loop over them mispredicted), then the rays, 4 at a time, of those
// with a body or wall in reach; nearest2 by slot. The block's divisions, square roots and grid look-ups
// come first, as a pass of their own: between the scans they waited on them. Returns the bodies kept.
template <bool kSparse>
SWARM_FORAGE_AVX2 std::size_t senseBlockX4(const Probe& p, std::size_t first, std::size_t count, BlockOut& o,
                                           double* nearest2) {
  std::size_t kept = 0;
  int cx[kBlock], cy[kBlock];
  UniformGrid::Run runs[kBlock][UniformGrid::kMaxRuns];
  uint8_t n_runs[kBlock];
  for (std::size_t b = 0; b < count; b += 4)
    cellsAndHeadingsX4(p, first + b, std::min<std::size_t>(4, count - b), o.hx + b, o.hy + b, cx + b, cy + b);
  for (std::size_t i = 0; i < count; ++i)
    n_runs[i] = static_cast<uint8_t>(p.grid->neighbourRuns(cx[i], cy[i], runs[i]));
  Pending q;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t s = first + i;
    if (q.used > kMaxPending) castPending(p, first, q, o);
    const double x = p.px[s], y = p.py[s];
    Scan sc{_mm256_set1_pd(x),
            _mm256_set1_pd(y),
            _mm256_set1_pd(1e300),
            _mm256_set1_epi64x(static_cast<long long>(s)),
            0,
            p.near_x + q.used,
            p.near_y + q.used};
    for (std::size_t r = 0; r < n_runs[i]; ++r) {
      const uint32_t k = runs[i][r].begin, e = runs[i][r].end;
      scanStep<kSparse>(p, sc, k, e);  // an empty run too: its lanes are all masked
      for (uint32_t k4 = k + 4; k4 < e; k4 += 4) scanStep<kSparse>(p, sc, k4, e);
    }
    alignas(32) double least[4];
    _mm256_store_pd(least, sc.nearest);
    // No NaN and no -0 among them: any order gives the scalar path's least value.
    nearest2[s] = std::min(std::min(least[0], least[1]), std::min(least[2], least[3]));
    const bool near_wall = (x < p.reach) | (y < p.reach) | (x > p.W - p.reach) | (y > p.H - p.reach);
    o.ox[i] = o.oy[i] = 0;
    o.threat[i] = false;
    q.at[q.count] = static_cast<uint32_t>(q.used);  // appended always, kept when it counts
    q.n[q.count] = static_cast<uint32_t>(sc.n);
    q.slot[q.count] = static_cast<uint8_t>(i);
    q.wall[q.count] = near_wall;
    q.count += (sc.n != 0) | near_wall;
    q.used += sc.n;
    kept += sc.n;
  }
  castPending(p, first, q, o);
  return kept;
}

}  // namespace

void World::senseSlotsX4(std::size_t first, std::size_t end, WorkerScratch& scratch) {
  const RobotConfig& rc = config_.robot;
  const bool occlusion = config_.quirks.has(Quirk::kLightOcclusion);
  Probe p{};
  p.px = sx_.data();
  p.py = sy_.data();
  p.pth = sth_.data();
  p.grid = &grid_;
  // With light_occlusion every robot that traces its lights turns them by its heading: when only carriers
  // do, theirs are taken one by one below (fastSinCos, the lanes' bits).
  p.all_headings = occlusion && !config_.light_only_carrying;
  p.ray_x = ray_x_.data();
  p.ray_y = ray_y_.data();
  p.n_rays = rays_.size();
  while (p.left_rays + 4 <= p.n_rays &&
         std::all_of(ray_y_.begin() + p.left_rays, ray_y_.begin() + p.left_rays + 4,
                     [](double y) { return y > 0; }))
    p.left_rays += 4;
  p.reach = 2 * rc.radius + rc.threat_distance;
  p.reach2 = p.reach * p.reach;
  p.W = config_.arena.width;
  p.H = config_.arena.height;
  p.s0 = rc.radius;
  p.s1 = rc.radius + rc.threat_distance;
  p.r2 = rc.radius * rc.radius;
  p.right_of = -rc.radius * (1 + 1e-9);  // the margin covers the roundings of the rays' exact test
  p.cell = grid_.cellSize();
  p.cols = grid_.columns();
  p.rows = grid_.rows();
  // Room for the bodies of the robots whose rays wait (at most kMaxPending before a scan, which keeps
  // fewer than the placed bodies) and the 4 lanes a compaction stores past its last: no scan needs a
  // check (a count of its slots, and a branch, per robot).
  const std::size_t room = grid_.placed() + kMaxPending + 4;
  if (scratch.near_x.size() < room) {
    scratch.near_x.resize(room);
    scratch.near_y.resize(room);
    scratch.near_d2.resize(room);
  }
  p.near_x = scratch.near_x.data();
  p.near_y = scratch.near_y.data();
  p.near_d2 = scratch.near_d2.data();
  BlockOut o;
  // Sparse scans (scanStep) once the blocks so far kept fewer bodies than a quarter of their robots, about
  // 1 step in 13 keeping one, where the two cost the same (measured).
  bool sparse = false;
  std::size_t kept = 0;
  // The robots that trace their lights (carriers, about 1 in 10) are listed here and traced after every
  // block's scans: a branch per robot on it mispredicted, and the tracing's branches, interleaved with the
  // scans, made the scans' mispredict.
  uint32_t traced[kChunk];
  std::size_t n_traced = 0;
  const uint8_t* const traces = traced_.data();
  for (std::size_t s = first; s < end; s += kBlock) {
    const std::size_t done = std::min(kBlock, end - s);
    kept += sparse ? senseBlockX4<true>(p, s, done, o, nearest2_.data())
                   : senseBlockX4<false>(p, s, done, o, nearest2_.data());
    sparse = 4 * kept < s + done - first;
    for (std::size_t i = 0; i < done; ++i) {
      const auto slot = static_cast<uint32_t>(s + i);
      if (occlusion) {  // the lights of those traced below
        traced[n_traced] = slot;
        n_traced += traces[slot];
        storeUntraced(slot, o.threat[i], o.ox[i], o.oy[i], slotGround(slot));
      } else {  // senseIds reads the lights
        storeReading(slot, 0, 0, o.threat[i], o.ox[i], o.oy[i], 0, 0, 0, slotGround(slot));
      }
    }
  }
  for (std::size_t j = 0; j < n_traced; ++j) {
    const uint32_t slot = traced[j];
    double lx, ly, hx, hy;
    uint8_t shadowed;
    shadowedLights(slot, lx, ly, shadowed);
    fastSinCos(sth_[slot], hy, hx);  // the 4-lane headings' bits
    toRobotFrame(hx, hy, lx, ly, readings_[slot].light_x, readings_[slot].light_y);
    sense_flags_[slot] |= static_cast<uint8_t>(shadowed << 1);
  }
}

}  // namespace swarm_forage
