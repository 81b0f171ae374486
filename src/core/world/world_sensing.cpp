// World::sense: proximity, light and ground for every robot, in parallel chunks of robots (each robot's
// readings depend only on the tick-start state, so any split gives the same readings).
#include <xmmintrin.h>

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/util/fast_math.hpp"
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
}  // namespace

static_assert(ArenaConfig::kLights <= 5, "sense_flags_ holds the shadowed lights in bits 3 to 7");
static_assert(kCacheGround <= 3, "sense_flags_ holds the ground in bits 1 and 2");

std::size_t World::chunks(std::size_t n) { return (n + kChunk - 1) / kChunk; }

void World::sense(SensorData& out) {
  ensureGrid();
  const std::size_t n = robots_.size();
  if (out.size() != n) out.resize(n);
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
  // Robots are sensed in slot order, neighbours of neighbours one after the other, so that the grid and
  // the positions a scan reads stay in cache; then the readings go to the robots' ids, in id order (two
  // threads writing scattered ids would keep taking each other's cache lines). Line of sight runs as
  // more tasks of the same two rounds: gathered with the sensing, copied into place with the readings.
  const std::size_t n_chunks = chunks(n), sight = config_.line_of_sight ? n_chunks : 0;
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
      sense_flags_[s] = kFloor << 1;
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
  if (occlusion) shadow_masks_.resize(n);
  pool_->run(n_chunks + sight, [&](std::size_t chunk, unsigned) {
    if (chunk >= n_chunks) return copySight(chunk - n_chunks, out);
    const auto [first, end] = chunkSpan(chunk, n);
    // The tick-start pose, events and carried blocks, in id order: robots_ holds what sortBodies copied
    // to the slots.
    float *const x = out.x.data(), *const y = out.y.data(), *const th = out.theta.data();
    const double *const px = robots_.x.data(), *const py = robots_.y.data(),
                        *const pth = robots_.theta.data();
    for (std::size_t i = first; i < end; ++i) {
      x[i] = static_cast<float>(px[i]);
      y[i] = static_cast<float>(py[i]);
      th[i] = static_cast<float>(pth[i]);
    }
    // Slots in id order are scattered: the reading a few ids ahead is fetched early (the loop waited on
    // those loads). Local pointers: after a byte store the compiler would reload every vector's data
    // pointer.
    const Reading* const rd = readings_.data();
    const uint8_t* const flags = sense_flags_.data();
    const uint32_t* const rank = grid_.rank().data();
    float *const ox = out.obstacle_x.data(), *const oy = out.obstacle_y.data();
    float *const lx = out.light_x.data(), *const ly = out.light_y.data();
    uint8_t *const threat = out.threatened.data(), *const ground = out.ground.data(),
                   *const ev = out.events.data();
    int32_t* const carried = out.carried_block.data();
    uint8_t* const shadow = shadow_masks_.data();
    std::copy(robots_.events.begin() + first, robots_.events.begin() + end, ev + first);
    std::copy(robots_.carried.begin() + first, robots_.carried.begin() + end, carried + first);
    constexpr std::size_t kAhead = 16;
    const auto flagsOf = [&](std::size_t i, uint32_t s) {
      const unsigned f = flags[s];
      threat[i] = f & 1u;
      ground[i] = (f >> 1) & 3u;
      if (occlusion) shadow[i] = static_cast<uint8_t>(f >> 3);
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
      _mm_storeu_ps(lx + i, r2);
      _mm_storeu_ps(ly + i, r3);
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
      lx[i] = r.light_x;
      ly[i] = r.light_y;
      flagsOf(i, s);
    }
  });
  if (occlusion) {
    shadowed_lights_ = 0;
    for (std::size_t s = 0; s < grid_.placed(); ++s)
      shadowed_lights_ += __builtin_popcount(sense_flags_[s] >> 3u);
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

  double lx, ly;
  uint8_t shadowed;
  lightVector(self, lx, ly, shadowed);
  storeReading(self, hx, hy, threat, best_x, best_y, lx, ly, shadowed);
}

void World::lightVector(uint32_t slot, double& light_x, double& light_y, uint8_t& shadowed) const {
  const double x = sx_[slot], y = sy_[slot];
  double lx = 0, ly = 0;
  shadowed = 0;  // light_occlusion: the lights a body shadows (world_quirks.cpp)
  const bool occlusion = config_.quirks.has(Quirk::kLightOcclusion);
  for (int l = 0; l < ArenaConfig::kLights; ++l) {
    const Vec2& p = lights_[l];
    if (occlusion && lightShadowed(slot, l)) {
      shadowed |= static_cast<uint8_t>(1u << l);
      continue;
    }
    const double dx = p.x() - x, dy = p.y() - y, len = std::sqrt(dx * dx + dy * dy);
    if (len > 1e-9) {
      const double inv = 1.0 / len;
      lx += dx * inv;
      ly += dy * inv;
    }
  }
  light_x = lx;
  light_y = ly;
}

}  // namespace swarm_forage
