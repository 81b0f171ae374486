// World motion: every robot's move for one tick, with collisions. Robots are indexed here by slot: their
// tick-start bodies sorted by grid cell, row-major (grid_.order(), grid_.rank()).
// They move in a fixed order that does not depend on the thread count: the arena is cut into horizontal
// bands of grid rows; the even bands move in parallel (in each, robots in slot order), then the odd ones.
// A band is tall enough that a robot's move never reads or writes a robot of another band of its parity,
// so each band's result is the same whichever thread runs it, and whenever.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "swarm_forage/core/util/fast_math.hpp"
#include "swarm_forage/core/util/fast_math_x4.hpp"
#include "swarm_forage/core/util/simd.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

namespace {
/// A body's coordinate clamped into [r, extent - r]: each axis on its own, so bodies slide along walls.
inline double inArena(double v, double r, double extent) { return std::clamp(v, r, extent - r); }

/// std::clamp(v, lo, hi) per lane in two instructions: hi < v ? hi : v (minpd's rule), then lo > that ? lo :
/// that (maxpd's): the same value for every v, NaN and zeros included.
template <int K>
SWARM_FORAGE_LANES lanes::D<K> clampMinMax(const lanes::D<K>& v, const lanes::D<K>& lo,
                                           const lanes::D<K>& hi) {
  lanes::D<K> out;
  for (int k = 0; k < K; ++k) out.v[k] = _mm256_max_pd(lo.v[k], _mm256_min_pd(hi.v[k], v.v[k]));
  return out;
}

/// World::commandedStep for the 4K slots from `th` on, robots order[0..4K) (with their wheel speeds clamped
/// to +-vmax and scaled by `scale`, carriers, or `other`; all by `scale` without `carried`), as K interleaved
/// groups of 4 lanes: the same operations per lane, gathered into registers (not through a buffer: 4 narrow
/// stores read back as one vector stall store forwarding). The rare heading that leaves [-pi, pi) is wrapped
/// by the scalar wrapAngle.
template <int K>
SWARM_FORAGE_LANES void commandedStepsN(const uint32_t* order, const CommandData& commands,
                                        const int32_t* carried, double scale, double other, double vmax,
                                        const double* th, double dt, double axle, double* step_x,
                                        double* step_y, double* step_th) {
  using namespace lanes;
  const float* cl = commands.left.data();
  const float* cr = commands.right.data();
  const __m256d carrier = _mm256_set1_pd(scale), walker = _mm256_set1_pd(other);
  D<K> f, l, r, t;
  for (int k = 0; k < K; ++k) {
    const uint32_t* o = order + 4 * k;
    const uint32_t i0 = o[0], i1 = o[1], i2 = o[2], i3 = o[3];
    if (carried) {  // carrier or not by a lane mask: as ternaries they were branches, often mispredicted
      const __m128i carries = _mm_cmpgt_epi32(
          _mm_setr_epi32(carried[i0], carried[i1], carried[i2], carried[i3]), _mm_set1_epi32(-1));
      f.v[k] = _mm256_blendv_pd(walker, carrier, _mm256_castsi256_pd(_mm256_cvtepi32_epi64(carries)));
    } else {
      f.v[k] = carrier;
    }
    l.v[k] = _mm256_cvtps_pd(_mm_setr_ps(cl[i0], cl[i1], cl[i2], cl[i3]));
    r.v[k] = _mm256_cvtps_pd(_mm_setr_ps(cr[i0], cr[i1], cr[i2], cr[i3]));
    t.v[k] = _mm256_loadu_pd(th + 4 * k);
  }
  const D<K> hi = set1<K>(vmax), lo = set1<K>(-vmax), vdt = set1<K>(dt);
  l = clampMinMax(l, lo, hi) * f;
  r = clampMinMax(r, lo, hi) * f;
  const D<K> v = set1<K>(0.5) * (l + r), w = (r - l) / set1<K>(axle);
  const D<K> mid = t + set1<K>(0.5) * w * vdt;
  const D<K> next = t + w * vdt;
  const D<K> in = cmp<_CMP_GE_OQ>(next, set1<K>(-kPi)) & cmp<_CMP_LT_OQ>(next, set1<K>(kPi));
  D<K> sm, cm;
  fastSinCosN<K>(mid, sm, cm);
  const D<K> sx = v * cm * vdt, sy = v * sm * vdt;
  for (int k = 0; k < K; ++k) {
    _mm256_storeu_pd(step_th + 4 * k, next.v[k]);
    if (const int wrapped = ~_mm256_movemask_pd(in.v[k]) & 0xf)
      for (int j = 0; j < 4; ++j)
        if (wrapped & (1 << j)) step_th[4 * k + j] = wrapAngle(step_th[4 * k + j]);
    _mm256_storeu_pd(step_x + 4 * k, sx.v[k]);
    _mm256_storeu_pd(step_y + 4 * k, sy.v[k]);
  }
}

/// Groups per call measured in CRW profiles: 4 took 5.0-5.6 % of it, 2 took 5.8-6.1 %, 1 took 5.1-6.1 %.
constexpr int kStepGroups = 4;
/// commandedStepsN for `groups` runs of 4 kStepGroups slots: one call, so the constants stay in registers.
SWARM_FORAGE_AVX2 void commandedStepsWide(std::size_t groups, const uint32_t* order,
                                          const CommandData& commands, const int32_t* carried, double scale,
                                          double other, double vmax, const double* th, double dt, double axle,
                                          double* step_x, double* step_y, double* step_th) {
  for (std::size_t g = 0, s = 0; g < groups; ++g, s += 4 * kStepGroups)
    commandedStepsN<kStepGroups>(order + s, commands, carried, scale, other, vmax, th + s, dt, axle,
                                 step_x + s, step_y + s, step_th + s);
}
SWARM_FORAGE_AVX2 void commandedSteps4(const uint32_t* order, const CommandData& commands,
                                       const int32_t* carried, double scale, double other, double vmax,
                                       const double* th, double dt, double axle, double* step_x,
                                       double* step_y, double* step_th) {
  commandedStepsN<1>(order, commands, carried, scale, other, vmax, th, dt, axle, step_x, step_y, step_th);
}

/// The moves of robots alone in slots [s, s + 4): each lane where nearest2 > apart2 takes its step within
/// the walls (inArena), the others keep their pose.
SWARM_FORAGE_AVX2 void moveAlone4(std::size_t s, const double* nearest2, double apart2, const double* step_x,
                                  const double* step_y, const double* step_th, double r, double width,
                                  double height, double* x, double* y, double* th) {
  using namespace lanes;
  D<1> x0, y0, dx, dy, t0, t1, near;
  x0.v[0] = _mm256_loadu_pd(x + s);
  y0.v[0] = _mm256_loadu_pd(y + s);
  dx.v[0] = _mm256_loadu_pd(step_x + s);
  dy.v[0] = _mm256_loadu_pd(step_y + s);
  t0.v[0] = _mm256_loadu_pd(th + s);
  t1.v[0] = _mm256_loadu_pd(step_th + s);
  near.v[0] = _mm256_loadu_pd(nearest2 + s);
  const D<1> alone = cmp<_CMP_GT_OQ>(near, set1<1>(apart2)), lo = set1<1>(r);
  _mm256_storeu_pd(x + s, blend(x0, clamp(x0 + dx, lo, set1<1>(width - r)), alone).v[0]);
  _mm256_storeu_pd(y + s, blend(y0, clamp(y0 + dy, lo, set1<1>(height - r)), alone).v[0]);
  _mm256_storeu_pd(th + s, blend(t0, t1, alone).v[0]);
}
}  // namespace

int World::bandRows(const WorldConfig& c, double cell) {
  // A robot moves at most m (a fully boosted carrier) and is pushed at most m / 2. Moving robot i reads
  // robots up to k1 + k2 + 2 rows from its tick-start row (its candidate positions: k1; the blocker's own
  // move and push: k2; one row of scan for each) and writes robots up to k1 + 1 rows away. Two bands of
  // one parity are a band apart: q + 1 > reads + writes.
  const double m = 2 * c.robot.max_speed * c.dt();
  const int k1 = static_cast<int>(std::ceil(m / cell)), k2 = static_cast<int>(std::ceil(1.5 * m / cell));
  if (!c.quirks.has(Quirk::kDynamics2dContacts)) return 2 * k1 + k2 + 3;
  // (9): the mover and its blocker may each have been pushed by up to m (k2c rows); a push moves bodies
  // up to kChainBodies bodies ahead (k3 rows, written) and scans one row beyond them (read). Reads
  // k1 + k2c + k3 + 2 rows, writes k1 + k2c + k3 + 1; one row more to spare.
  const int k3 = static_cast<int>(std::ceil((kChainBodies * (2 * c.robot.radius + m) + m) / cell));
  const int k2c = static_cast<int>(std::ceil(2 * m / cell));
  return 2 * (k1 + k2c + k3) + 4;
}

void World::buildGrid() {
  // Inactive robots are in no cell. Within a band robots move in id order, as before there were bands: an
  // order that follows space (say, row by row) would let a queue flow one way and jam the other.
  band_order_.rows = band_rows_;
  grid_.build(robots_.x.data(), robots_.y.data(), robots_.size(), activeMask(), &band_order_);
  // Slots are sorted by cell, row-major, so a band of band_rows_ rows is a contiguous slot range.
  for (auto& band : bands_) band.clear();
  const std::vector<uint32_t>& start = band_order_.start;
  for (std::size_t b = 0; b + 1 < start.size(); ++b)
    if (start[b] < start[b + 1]) bands_[b & 1].emplace_back(start[b], start[b + 1]);
}

void World::copyToSlots() {
  const std::size_t n = robots_.size();
  const std::vector<uint32_t>& order = grid_.order();
  sx_.resize(n);
  sy_.resize(n);
  sth_.resize(n);
  pool_->run(chunks(n), [&](std::size_t chunk, unsigned) {
    const auto [first, end] = chunkSpan(chunk, n);
    for (std::size_t s = first; s < end; ++s) {
      const uint32_t i = order[s];
      sx_[s] = robots_.x[i];
      sy_[s] = robots_.y[i];
      sth_[s] = robots_.theta[i];
    }
  });
}

void World::moveAll(const CommandData& commands, double scale, double other_scale) {
  const std::size_t n = robots_.size();
  pushed_.assign(n, 0);
  const double vmax = config_.robot.max_speed, r = config_.robot.radius;
  const bool parallel = n >= 2 * kChunk;
  // A robot whose nearest neighbour at sense time was farther than 2r + 3m (it moves m at most, the
  // neighbour m and a push of m / 2, and it may have been pushed m / 2 itself) cannot touch anyone this
  // tick: only the walls can stop it. Sense scans one grid cell around a robot, so this needs
  // 2r + 3m < cell.
  const bool contacts = config_.quirks.has(Quirk::kDynamics2dContacts);
  if (contacts) prepareContacts(commands, scale, other_scale);
  // (9): a body may be pushed by up to m (push_left_), not m / 2.
  const double m = vmax * dt_ * std::max({1.0, std::abs(scale), std::abs(other_scale)}),
               apart = 2 * r + (contacts ? 4 : 3) * m;
  const bool use_clearance = clearance_valid_ && apart < grid_.cellSize();
  // Each robot's commanded step and new heading depend on its own tick-start pose and command only: all
  // of them first, in parallel and with many robots' sine chains in flight; the moves then resolve contacts.
  const uint32_t placed = grid_.placed();
  step_x_.resize(n);
  step_y_.resize(n);
  step_th_.resize(n);
  const bool simd = simdEnabled();
  const double apart2 = apart * apart;
  const auto alone = [&](uint32_t s) { return use_clearance && nearest2_[s] > apart2; };
  // The usual case, one scale for all (the same bits): the 4-lane steps need not read who carries.
  const int32_t* carried =
      std::memcmp(&scale, &other_scale, sizeof scale) == 0 ? nullptr : robots_.carried.data();
  pool_->run(chunks(placed), [&](std::size_t chunk, unsigned) {
    const auto [first, end] = chunkSpan(chunk, placed);
    std::size_t s = first;
    if (simd) {
      const std::size_t groups = (end - s) / (4 * kStepGroups);
      commandedStepsWide(groups, &grid_.order()[s], commands, carried, scale, other_scale, vmax, &sth_[s],
                         dt_, config_.robot.axle, &step_x_[s], &step_y_[s], &step_th_[s]);
      s += groups * 4 * kStepGroups;
      for (; s + 4 <= end; s += 4)
        commandedSteps4(&grid_.order()[s], commands, carried, scale, other_scale, vmax, &sth_[s], dt_,
                        config_.robot.axle, &step_x_[s], &step_y_[s], &step_th_[s]);
    }
    for (; s < end; ++s) {
      const uint32_t i = grid_.order()[s];
      const double f = robots_.carried[i] >= 0 ? scale : other_scale;
      commandedStep(static_cast<uint32_t>(s), std::clamp<double>(commands.left[i], -vmax, vmax) * f,
                    std::clamp<double>(commands.right[i], -vmax, vmax) * f);
    }
    // A robot alone moves here, in slot order, not in the bands: no other robot's move comes within 2r of
    // it, before or after its move (the bounds above), so its move commutes with all of theirs. Its move
    // is its step within the walls, as selects: alone or not is a coin flip for the branch predictor.
    const double width = config_.arena.width, height = config_.arena.height;
    s = first;
    if (simd && use_clearance)
      for (; s + 4 <= end; s += 4)
        moveAlone4(s, nearest2_.data(), apart2, step_x_.data(), step_y_.data(), step_th_.data(), r, width,
                   height, sx_.data(), sy_.data(), sth_.data());
    for (; s < end; ++s) {
      const bool a = alone(static_cast<uint32_t>(s));
      const double x = inArena(sx_[s] + step_x_[s], r, width), y = inArena(sy_[s] + step_y_[s], r, height);
      sx_[s] = a ? x : sx_[s];
      sy_[s] = a ? y : sy_[s];
      sth_[s] = a ? step_th_[s] : sth_[s];
    }
  });
  // Even bands first on even ticks, odd ones on odd ticks: neither side of a band's edge always goes first.
  for (const int parity : {static_cast<int>(tick_ & 1), static_cast<int>(~tick_ & 1)}) {
    const auto& bands = bands_[parity];
    const auto moveBand = [&](std::size_t k, unsigned) {
      // The band's robots that are not alone, kept in order at the front of its range without a branch
      // (band_order_ is this tick's, rebuilt by the next buildGrid()); then their moves.
      uint32_t busy = bands[k].first;
      for (uint32_t o = bands[k].first; o < bands[k].second; ++o) {
        const uint32_t s = band_order_.order[o];
        band_order_.order[busy] = s;
        busy += alone(s) ? 0 : 1;
      }
      for (uint32_t o = bands[k].first; o < busy; ++o) move(band_order_.order[o]);
    };
    if (parallel)
      pool_->run(bands.size(), moveBand);
    else
      for (std::size_t k = 0; k < bands.size(); ++k) moveBand(k, 0);
  }
  clearance_valid_ = false;
  const std::vector<uint32_t>& slot = grid_.rank();
  pool_->run(chunks(n), [&](std::size_t chunk, unsigned) {  // in id order: each thread writes its own lines
    const auto [first, end] = chunkSpan(chunk, n);
    for (std::size_t i = first; i < end; ++i) {
      robots_.x[i] = sx_[slot[i]];
      robots_.y[i] = sy_[slot[i]];
      robots_.theta[i] = sth_[slot[i]];
    }
  });
}

bool World::fits(uint32_t i, double x, double y) const {
  const double r = config_.robot.radius, d2 = 4 * r * r;
  if (x < r || y < r || x > config_.arena.width - r || y > config_.arena.height - r) return false;
  bool ok = true;
  grid_.forNeighbours(x, y, [&](uint32_t j) {
    if (j == i) return;
    const double dx = sx_[j] - x, dy = sy_[j] - y;
    if (dx * dx + dy * dy < d2) ok = false;
  });
  return ok;
}

void World::commandedStep(uint32_t i, double left, double right) {
  const double dt = dt_;
  const double v = 0.5 * (left + right), w = (right - left) / config_.robot.axle;
  const double th = sth_[i];
  const double mid = th + 0.5 * w * dt;
  step_th_[i] = wrapAngle(th + w * dt);
  double sm, cm;
  fastSinCos(mid, sm, cm);
  step_x_[i] = v * cm * dt;
  step_y_[i] = v * sm * dt;
}

void World::move(uint32_t i) {
  sth_[i] = step_th_[i];
  const double r = config_.robot.radius;
  const double x0 = sx_[i], y0 = sy_[i];
  const double dx = step_x_[i], dy = step_y_[i];
  const auto inside = [&](double x, double y) {  // each axis on its own: bodies slide along walls
    return std::make_pair(inArena(x, r, config_.arena.width), inArena(y, r, config_.arena.height));
  };
  const auto tryMove = [&](double mx, double my) {  // taken only if it keeps every body apart
    const auto [x, y] = inside(x0 + mx, y0 + my);
    if (!fits(i, x, y)) return false;  // inside() keeps it off the walls
    sx_[i] = x;
    sy_[i] = y;
    return true;
  };
  if (tryMove(dx, dy)) return;
  // Blocked: slide along the contact, as a body in ARGoS' physics slips past the one it touches (the walls
  // already slide: each axis is clamped on its own). Without it, crowds lock up at the nest edge.
  int32_t j = blocker(i, x0 + dx, y0 + dy);
  if (config_.quirks.has(Quirk::kDynamics2dContacts)) {  // (9): pushes as ARGoS' drives do, then slides
    double fx = 0, fy = 0;
    if (j >= 0 && pushChain(i, dx, dy, fx, fy)) {
      if (tryMove(dx, dy)) return;
      j = blocker(i, x0 + dx, y0 + dy);
      if (j >= 0 && tryMove(fx, fy)) return;  // behind the bodies it pushed
    }
  } else if (j >= 0 && !pushed_[j]) {
    // Push the blocker along the line of centres by half the move's component into it (equal bodies
    // share it), once per tick, if it has room: a crowd driving into another flows, as in ARGoS.
    double nx = sx_[j] - x0, ny = sy_[j] - y0;
    const double nlen = std::hypot(nx, ny);
    const double into = nlen > 1e-12 ? (dx * nx + dy * ny) / nlen : 0.0;
    if (into > 0) {
      nx /= nlen;
      ny /= nlen;
      const auto [jx, jy] = inside(sx_[j] + 0.5 * into * nx, sy_[j] + 0.5 * into * ny);
      if (fits(static_cast<uint32_t>(j), jx, jy)) {
        sx_[j] = jx;
        sy_[j] = jy;
        pushed_[j] = 1;
        if (tryMove(dx, dy)) return;
      }
    }
  }
  if (j >= 0) {
    double tx = -(sy_[j] - y0), ty = sx_[j] - x0;  // perpendicular to the line of centres
    const double len = std::hypot(tx, ty);
    if (len > 1e-12) {
      tx /= len;
      ty /= len;
      const double along = dx * tx + dy * ty;
      for (double frac : {1.0, 0.5})
        if (tryMove(frac * along * tx, frac * along * ty)) return;
    }
  }
  tryMove(0.5 * dx, 0.5 * dy);
}

int32_t World::blocker(uint32_t i, double x, double y) const {
  const double d2 = 4 * config_.robot.radius * config_.robot.radius;
  int32_t nearest = -1;
  double best = d2;
  grid_.forNeighbours(x, y, [&](uint32_t j) {
    if (j == i) return;
    const double ex = sx_[j] - x, ey = sy_[j] - y, e2 = ex * ex + ey * ey;
    if (e2 < best) {
      best = e2;
      nearest = static_cast<int32_t>(j);
    }
  });
  return nearest;
}

}  // namespace swarm_forage
