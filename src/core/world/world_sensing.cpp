// World::sense: proximity, light and ground for every robot, in parallel chunks of robots (each robot's
// readings depend only on the tick-start state, so any split gives the same readings).
#include <immintrin.h>

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/util/fast_math.hpp"
#include "swarm_forage/core/util/fast_math_x4.hpp"
#include "swarm_forage/core/util/simd.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

namespace {
// The foot-bot's 24 proximity rays, in ARGoS' sensor order (sensor k at 7.5 + 15k degrees, counter-
// clockwise from the front), those within the field of view. FORDYCA's closest_prox_obj keeps the first
// ray that reads anything: its "closer" test compares the robot's world position with a reading, which
// never holds, so the order decides. Obstacles on the left win over those on the right, and a robot
// dodges a body ahead of it to the right: crowds pass each other instead of locking up head on.
std::vector<Vec2> proximityRays(double fov) {
  std::vector<Vec2> rays;
  for (int k = 0; k < 24; ++k) {
    const double a = wrapAngle(deg2rad(7.5 + 15.0 * k));
    if (std::abs(a) <= fov + 1e-12) rays.emplace_back(std::cos(a), std::sin(a));
  }
  return rays;
}

// The sum of unit vectors from (x, y) to the lights, map frame (light_occlusion.cpp sums them the same way).
inline void lightSum(const Vec2* lights, double x, double y, double& light_x, double& light_y) {
  double lx = 0, ly = 0;
  for (int l = 0; l < ArenaConfig::kLights; ++l) {
    const double dx = lights[l].x() - x, dy = lights[l].y() - y, len = std::sqrt(dx * dx + dy * dy);
    if (len > 1e-9) {
      const double inv = 1.0 / len;
      lx += dx * inv;
      ly += dy * inv;
    }
  }
  light_x = lx;
  light_y = ly;
}

// The light reading (robot frame, as toRobotFrame turns it) of robots [first, end) in id order, 4 at a
// time: lightSum's and fastSinCos's IEEE operations per lane, the same bits. end - first a multiple of 4.
SWARM_FORAGE_AVX2 void lightReadingsX4(const Vec2* lights, const double* px, const double* py,
                                       const double* pth, std::size_t first, std::size_t end, float* out_x,
                                       float* out_y) {
  const __m256d tiny = _mm256_set1_pd(1e-9), one = _mm256_set1_pd(1.0), sign = _mm256_set1_pd(-0.0);
  for (std::size_t i = first; i < end; i += 4) {
    const __m256d x = _mm256_loadu_pd(px + i), y = _mm256_loadu_pd(py + i);
    __m256d ax = _mm256_setzero_pd(), ay = _mm256_setzero_pd();
    for (int l = 0; l < ArenaConfig::kLights; ++l) {
      const __m256d dx = _mm256_sub_pd(_mm256_set1_pd(lights[l].x()), x);
      const __m256d dy = _mm256_sub_pd(_mm256_set1_pd(lights[l].y()), y);
      const __m256d len = _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)));
      const __m256d on = _mm256_cmp_pd(len, tiny, _CMP_GT_OQ), inv = _mm256_div_pd(one, len);
      ax = _mm256_blendv_pd(ax, _mm256_add_pd(ax, _mm256_mul_pd(dx, inv)), on);
      ay = _mm256_blendv_pd(ay, _mm256_add_pd(ay, _mm256_mul_pd(dy, inv)), on);
    }
    __m256d hy, hx;
    fastSinCos4(_mm256_loadu_pd(pth + i), hy, hx);
    // hx lx + hy ly and (-hy) lx + hx ly, as toRobotFrame computes them
    const __m256d fx = _mm256_add_pd(_mm256_mul_pd(hx, ax), _mm256_mul_pd(hy, ay));
    const __m256d fy = _mm256_add_pd(_mm256_mul_pd(_mm256_xor_pd(hy, sign), ax), _mm256_mul_pd(hx, ay));
    _mm_storeu_ps(out_x + i, _mm256_cvtpd_ps(fx));
    _mm_storeu_ps(out_y + i, _mm256_cvtpd_ps(fy));
  }
}
}  // namespace

static_assert(ArenaConfig::kLights <= 3, "sense_flags_ holds the shadowed lights in bits 1 to 3");

std::size_t World::chunks(std::size_t n) { return (n + kChunk - 1) / kChunk; }

void World::sense(SensorData& out) {
  const std::size_t n = robots_.size();
  if (out.size() != n) out.resize(n);
  const std::size_t n_chunks = chunks(n);
  // First what needs no grid, by id: the grid's build is serial, and the other threads do this meanwhile.
  const bool build = !grid_valid_;
  pool_->run((build ? 1 : 0) + n_chunks, [&](std::size_t task, unsigned) {
    if (build && task == 0) return buildGrid();
    const auto [first, end] = chunkSpan(task - (build ? 1 : 0), n);
    senseIds(first, end, out);
  });
  if (build) slotGrid();
  if (rays_.empty()) {
    rays_ = proximityRays(config_.robot.fov);
    ray_x_.assign((rays_.size() + 3) / 4 * 4, 0.0);
    ray_y_.assign(ray_x_.size(), 0.0);
    for (std::size_t k = 0; k < rays_.size(); ++k) {
      ray_x_[k] = rays_[k].x();
      ray_y_[k] = rays_[k].y();
    }
  }
  const bool x4 = simdEnabled();
  scratch_.resize(pool_->threads());
  nearest2_.resize(n);
  readings_.resize(n);
  sense_flags_.resize(n);
  if (config_.quirks.has(Quirk::kLightOcclusion)) {
    shadow_witness_.resize(n * ArenaConfig::kLights, kNoWitness);
    prepareShadows();
  }
  // Robots are sensed in slot order, neighbours of neighbours one after the other, so that the grid and
  // the positions a scan reads stay in cache; then the readings go to the robots' ids, in id order (two
  // threads writing scattered ids would keep taking each other's cache lines). Line of sight runs as
  // more tasks of the same two rounds: gathered with the sensing, copied into place with the readings.
  const std::size_t sight = config_.line_of_sight ? n_chunks : 0;
  los_.resize(sight);
  if (sight) sight_.build(config_.sight, config_.arena, blocks_, cache_);
  pool_->run(n_chunks + sight, [&](std::size_t task, unsigned worker) {
    if (task >= n_chunks) return gatherSight(task - n_chunks);
    const auto [first, end] = chunkSpan(task, n);
    const std::size_t placed = std::min<std::size_t>(end, grid_.placed());
    if (x4)
      senseSlotsX4(first, std::max(first, placed), scratch_[worker]);
    else
      for (std::size_t s = first; s < placed; ++s)
        senseRobot(static_cast<uint32_t>(s), scratch_[worker].near);
    for (std::size_t s = std::max(first, placed); s < end; ++s) {  // out of the swarm: its pose only
      readings_[s] = Reading{0, 0, 0, 0};
      sense_flags_[s] = 0;
      nearest2_[s] = 0;  // never `alone`: it does not move anyway
    }
  });
  if (const uint8_t* mask = activeMask())
    out.active.assign(mask, mask + n);
  else
    out.active.clear();
  if (sight)
    layOutSight(out);
  else if (out.hasLineOfSight())
    out.clearLineOfSight();
  const bool occlusion = config_.quirks.has(Quirk::kLightOcclusion);
  const bool rim = config_.quirks.has(Quirk::kRimGroundSensors);
  if (occlusion) {
    shadow_masks_.resize(n);
    shadow_counts_.assign(n_chunks, 0);
  }
  pool_->run(n_chunks + sight, [&](std::size_t chunk, unsigned) {
    if (chunk >= n_chunks) return copySight(chunk - n_chunks, out);
    const auto [first, end] = chunkSpan(chunk, n);
    // Slots in id order are scattered: the reading a few ids ahead is fetched early (the loop waited on
    // those loads). Local pointers: after a byte store the compiler would reload every vector's data
    // pointer.
    const Reading* const rd = readings_.data();
    const uint8_t* const flags = sense_flags_.data();
    const uint32_t* const rank = grid_.rank().data();
    float *const ox = out.obstacle_x.data(), *const oy = out.obstacle_y.data();
    float *const lx = out.light_x.data(), *const ly = out.light_y.data();  // here with light_occlusion only
    uint8_t* const threat = out.threatened.data();
    uint8_t* const shadow = shadow_masks_.data();
    uint8_t* const ground = out.ground.data();  // here with rim_ground_sensors only
    constexpr std::size_t kAhead = 16;
    // The shadowed lights counted here, chunk by chunk, where the masks are read anyway: 0xE994 holds the
    // number of set bits of m = 0..7 in its bits 2m and 2m + 1 (no popcnt in the baseline x86-64).
    uint64_t shadows = 0;
    const auto flagsOf = [&](std::size_t i, uint32_t s) {
      const unsigned f = flags[s];
      threat[i] = f & 1u;
      if (occlusion) {
        const unsigned m = f >> 1 & 7u;
        shadow[i] = static_cast<uint8_t>(m);
        shadows += 0xE994u >> (2 * m) & 3u;
      }
      if (rim) ground[i] = static_cast<uint8_t>(f >> 4 & 3u);
    };
    std::size_t i = first;
    // 4 robots at a time: their 4 readings are 4 fields of 4, a transpose (SSE, in every x86-64: no
    // AVX2 check; moves only, the same bits).
    for (; i + 4 <= end; i += 4) {
      if (i + kAhead + 4 <= end)
        for (std::size_t k = 0; k < 4; ++k) __builtin_prefetch(rd + rank[i + kAhead + k]);
      const uint32_t s0 = rank[i], s1 = rank[i + 1], s2 = rank[i + 2], s3 = rank[i + 3];
      __m128 r0 = _mm_load_ps(&rd[s0].obstacle_x), r1 = _mm_load_ps(&rd[s1].obstacle_x),
             r2 = _mm_load_ps(&rd[s2].obstacle_x), r3 = _mm_load_ps(&rd[s3].obstacle_x);
      _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
      _mm_storeu_ps(ox + i, r0);
      _mm_storeu_ps(oy + i, r1);
      if (occlusion) {
        _mm_storeu_ps(lx + i, r2);
        _mm_storeu_ps(ly + i, r3);
      }
      flagsOf(i, s0);
      flagsOf(i + 1, s1);
      flagsOf(i + 2, s2);
      flagsOf(i + 3, s3);
    }
    for (; i < end; ++i) {
      const uint32_t s = rank[i];
      const Reading r = rd[s];
      ox[i] = r.obstacle_x;
      oy[i] = r.obstacle_y;
      if (occlusion) {
        lx[i] = r.light_x;
        ly[i] = r.light_y;
      }
      flagsOf(i, s);
    }
    if (occlusion) shadow_counts_[chunk] = shadows;
  });
  if (occlusion) {
    clearShadowCells();
    shadowed_lights_ = 0;
    for (const uint64_t c : shadow_counts_) shadowed_lights_ += c;
  }
  clearance_valid_ = true;
  if (config_.noise.sensorsOn()) perceive(out);
}

void World::perceive(const SensorData& sensed) {
  perceived_ = sensed;  // line of sight too: the blocks and caches seen are where they are
  const std::size_t n = sensed.size();
  const int ground_kinds = config_.cache.enabled ? 4 : 3;
  pool_->run(chunks(n), [&](std::size_t chunk, unsigned) {
    const auto [first, end] = chunkSpan(chunk, n);
    config_.noise.perturbReadings(perceived_, first, end, config_.seed, tick_, ground_kinds);
  });
}

void World::senseRobot(uint32_t self, std::vector<NearBody>& near) {
  const RobotConfig& rc = config_.robot;
  const double W = config_.arena.width, H = config_.arena.height;
  const double reach = 2 * rc.radius + rc.threat_distance;
  const double x = sx_[self], y = sy_[self], th = sth_[self];
  double hx, hy;
  fastSinCos(th, hy, hx);
  // FORDYCA's threatening obstacle: the first of the foot-bot's proximity rays, in sensor order, that
  // sees something within the threat distance (see proximityRays()).
  near.clear();
  double nearest2 = 1e300;
  // Local copies: the compiler cannot tell that push_back leaves sx_ and sy_ alone.
  const double* const px = sx_.data();
  const double* const py = sy_.data();
  const double reach2 = reach * reach;
  grid_.forNeighbours(x, y, [&](uint32_t j) {
    if (j == self) return;
    const double dx = px[j] - x, dy = py[j] - y, d2 = dx * dx + dy * dy;
    nearest2 = std::min(nearest2, d2);
    if (d2 < reach2) near.push_back({hx * dx + hy * dy, -hy * dx + hx * dy, d2});  // robot frame
  });
  nearest2_[self] = nearest2;
  const bool near_wall = x < reach || y < reach || x > W - reach || y > H - reach;
  double best_x = 0, best_y = 0;
  bool threat = false;
  if (!near.empty() || near_wall) {
    const double s0 = rc.radius, s1 = rc.radius + rc.threat_distance, r2 = rc.radius * rc.radius;
    for (const Vec2& ray : rays_) {
      // Whether the ray passes through any body at all: a branch-free pass with the very test the exact
      // loop below starts with (most rays before the first hit pass through nothing).
      bool through = near_wall;
      for (const NearBody& w : near) {
        const double along = w.x * ray.x() + w.y * ray.y(), q2 = w.d2 - along * along;
        through |= (along > 0) & (q2 < r2);
      }
      if (!through) continue;
      double hit = -1;  // distance from the centre along the ray to the first body or wall it meets
      if (near_wall) {
        const double ux = hx * ray.x() - hy * ray.y(), uy = hy * ray.x() + hx * ray.y();
        const double tx = ux < 0 ? x / -ux : ux > 0 ? (W - x) / ux : 1e9;
        const double ty = uy < 0 ? y / -uy : uy > 0 ? (H - y) / uy : 1e9;
        if (std::min(tx, ty) <= s1) hit = std::max(std::min(tx, ty), s0);
      }
      for (const NearBody& w : near) {
        const double along = w.x * ray.x() + w.y * ray.y();
        const double q2 = w.d2 - along * along;  // squared distance of the centre from the ray
        if (along <= 0 || q2 >= r2) continue;
        const double entry = along - std::sqrt(r2 - q2);  // >= s0: bodies never overlap
        if (entry <= s1 && (hit < 0 || entry < hit)) hit = std::max(entry, s0);
      }
      if (hit >= 0) {  // the reading in the robot frame: the ray itself, scaled
        best_x = hit * ray.x();
        best_y = hit * ray.y();
        threat = true;
        break;
      }
    }
  }

  double lx = 0, ly = 0;  // without light_occlusion, senseIds reads them
  uint8_t shadowed = 0;
  if (config_.quirks.has(Quirk::kLightOcclusion)) occludedLights(self, lx, ly, shadowed);
  storeReading(self, hx, hy, threat, best_x, best_y, lx, ly, shadowed, slotGround(self));
}

void World::senseIds(std::size_t first, std::size_t end, SensorData& out) const {
  const double *const px = robots_.x.data(), *const py = robots_.y.data(), *const pth = robots_.theta.data();
  float *const x = out.x.data(), *const y = out.y.data(), *const th = out.theta.data();
  for (std::size_t i = first; i < end; ++i) {
    x[i] = static_cast<float>(px[i]);
    y[i] = static_cast<float>(py[i]);
    th[i] = static_cast<float>(pth[i]);
  }
  if (!config_.quirks.has(Quirk::kRimGroundSensors))  // else by slot, with the sensing (slotGround)
    for (std::size_t i = first; i < end; ++i) out.ground[i] = groundAt(px[i], py[i]);
  std::copy(robots_.events.begin() + first, robots_.events.begin() + end, out.events.begin() + first);
  std::copy(robots_.carried.begin() + first, robots_.carried.begin() + end,
            out.carried_block.begin() + first);
  if (!config_.quirks.has(Quirk::kLightOcclusion)) {
    float *const lx = out.light_x.data(), *const ly = out.light_y.data();
    std::size_t i = first;
    if (simdEnabled()) {
      i = end - (end - first) % 4;
      lightReadingsX4(lights_, px, py, pth, first, i, lx, ly);
    }
    for (; i < end; ++i) {
      double hx, hy, sx, sy;
      fastSinCos(pth[i], hy, hx);
      lightSum(lights_, px[i], py[i], sx, sy);
      toRobotFrame(hx, hy, sx, sy, lx[i], ly[i]);
    }
  }
  if (const uint8_t* mask = activeMask())  // out of the swarm: its pose only
    for (std::size_t i = first; i < end; ++i)
      if (!mask[i]) {
        out.ground[i] = kFloor;
        out.light_x[i] = out.light_y[i] = 0;
      }
}

}  // namespace swarm_forage
