#include "swarm_forage/core/world.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "swarm_forage/core/rng.hpp"

namespace swarm_forage {

namespace {
// A 3x3 query must reach the threat distance, and a neighbour's tick-start cell even after it moved
// this tick (at most 2 x max_speed x dt, a fully boosted carrier).
double gridCell(const WorldConfig& c) {
  const RobotConfig& r = c.robot;
  return 2 * r.radius + std::max(r.threat_distance, 2 * r.max_speed * c.dt()) + 0.01;
}

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

World::World(const WorldConfig& config) : config_(config) {
  config_.validate();
  reset(config.seed, config.n_robots);
}

void World::reset(uint32_t seed, uint32_t n_robots) {
  WorldConfig next = config_;
  next.seed = seed;
  next.n_robots = n_robots;
  next.validate();
  config_ = next;
  tick_ = 0;
  cumulative_ = 0;
  grid_ = UniformGrid(config_.arena.width, config_.arena.height, gridCell(config_));
  blocks_.init(config_.arena, seed);
  cache_.init(config_.arena, config_.cache);
  if (config_.cache.enabled) cache_.create(blocks_);
  placeRobots();
}

void World::placeRobots() {
  const uint32_t n = config_.n_robots;
  robots_.x.assign(n, 0);
  robots_.y.assign(n, 0);
  robots_.theta.assign(n, 0);
  robots_.carried.assign(n, -1);
  robots_.events.assign(n, 0);
  robots_.last_request.assign(n, kNone);
  robots_.request_since.assign(n, 0);
  grid_.clear();
  const Rect s = config_.arena.start();
  for (uint32_t i = 0; i < n; ++i) {
    CounterRng rng(config_.seed, RngStream::kPlacement, i, 0);
    bool placed = false;
    for (int attempt = 0; attempt < 10000 && !placed; ++attempt) {
      const double x = rng.uniform(s.min_x, s.max_x), y = rng.uniform(s.min_y, s.max_y);
      robots_.x[i] = x;
      robots_.y[i] = y;
      if (!fits(i, x, y)) continue;
      robots_.theta[i] = rng.uniform(-kPi, kPi);
      grid_.insert(i, x, y);
      placed = true;
    }
    if (!placed)
      throw ParameterError("n_robots " + std::to_string(n) + " do not fit the start region of a " +
                           config_.arena.name + " arena (placed " + std::to_string(i) + ")");
  }
  grid_valid_ = false;
}

bool World::fits(uint32_t i, double x, double y) const {
  const double r = config_.robot.radius, d2 = 4 * r * r;
  if (x < r || y < r || x > config_.arena.width - r || y > config_.arena.height - r) return false;
  bool ok = true;
  grid_.forNeighbours(x, y, [&](uint32_t j) {
    if (j == i) return;
    const double dx = robots_.x[j] - x, dy = robots_.y[j] - y;
    if (dx * dx + dy * dy < d2) ok = false;
  });
  return ok;
}

void World::ensureGrid() {
  if (grid_valid_) return;
  grid_.build(robots_.x.data(), robots_.y.data(), robots_.size());
  grid_valid_ = true;
}

uint8_t World::groundAt(double x, double y) const {
  if (config_.arena.nest().contains(x, y)) return kNest;
  if (cache_.contains(x, y)) return kCacheGround;
  if (blocks_.blockAt(x, y) >= 0) return kBlockGround;
  return kFloor;
}

uint32_t World::carrying() const {
  return static_cast<uint32_t>(
      std::count_if(robots_.carried.begin(), robots_.carried.end(), [](int32_t b) { return b >= 0; }));
}

void World::sense(SensorData& out) {
  ensureGrid();
  const std::size_t n = robots_.size();
  if (out.size() != n) out.resize(n);
  const RobotConfig& rc = config_.robot;
  const double W = config_.arena.width, H = config_.arena.height;
  const double reach = 2 * rc.radius + rc.threat_distance;
  Vec2 lights[ArenaConfig::kLights];
  for (int l = 0; l < ArenaConfig::kLights; ++l) lights[l] = config_.arena.light(l);
  if (rays_.empty()) rays_ = proximityRays(rc.fov);

  for (std::size_t i = 0; i < n; ++i) {
    const double x = robots_.x[i], y = robots_.y[i], th = robots_.theta[i];
    const double hx = std::cos(th), hy = std::sin(th);
    // FORDYCA's threatening obstacle: the first of the foot-bot's proximity rays, in sensor order, that
    // sees something within the threat distance (see proximityRays()).
    near_.clear();
    grid_.forNeighbours(x, y, [&](uint32_t j) {
      if (j == i) return;
      const double dx = robots_.x[j] - x, dy = robots_.y[j] - y;
      if (dx * dx + dy * dy < reach * reach) near_.emplace_back(dx, dy);
    });
    const bool near_wall = x < reach || y < reach || x > W - reach || y > H - reach;
    Vec2 best(0, 0);
    bool threat = false;
    if (!near_.empty() || near_wall) {
      const double s0 = rc.radius, s1 = rc.radius + rc.threat_distance;
      for (const Vec2& ray : rays_) {
        const double ux = hx * ray.x() - hy * ray.y(), uy = hy * ray.x() + hx * ray.y();
        double hit = -1;  // distance from the centre along the ray to the first body or wall it meets
        const double tx = ux < 0 ? x / -ux : ux > 0 ? (W - x) / ux : 1e9;
        const double ty = uy < 0 ? y / -uy : uy > 0 ? (H - y) / uy : 1e9;
        if (std::min(tx, ty) <= s1) hit = std::max(std::min(tx, ty), s0);
        for (const Vec2& w : near_) {
          const double along = w.x() * ux + w.y() * uy;
          const double qx = w.x() - along * ux, qy = w.y() - along * uy, q2 = qx * qx + qy * qy;
          if (along <= 0 || q2 >= rc.radius * rc.radius) continue;
          const double entry = along - std::sqrt(rc.radius * rc.radius - q2);  // >= s0: bodies never overlap
          if (entry <= s1 && (hit < 0 || entry < hit)) hit = std::max(entry, s0);
        }
        if (hit >= 0) {
          best = Vec2(hit * ux, hit * uy);
          threat = true;
          break;
        }
      }
    }

    Vec2 light(0, 0);
    for (const Vec2& l : lights) {
      const Vec2 d(l.x() - x, l.y() - y);
      const double len = d.norm();
      if (len > 1e-9) light += d / len;
    }
    const Vec2 ob = toRobotFrame(best, th), lr = toRobotFrame(light, th);

    out.x[i] = static_cast<float>(x);
    out.y[i] = static_cast<float>(y);
    out.theta[i] = static_cast<float>(th);
    out.threatened[i] = threat ? 1 : 0;
    out.obstacle_x[i] = static_cast<float>(ob.x());
    out.obstacle_y[i] = static_cast<float>(ob.y());
    out.light_x[i] = static_cast<float>(lr.x());
    out.light_y[i] = static_cast<float>(lr.y());
    out.ground[i] = groundAt(x, y);
    out.events[i] = robots_.events[i];
    out.carried_block[i] = robots_.carried[i];
  }
  if (config_.line_of_sight)
    senseLineOfSight(out);
  else if (out.hasLineOfSight())
    out.clearLineOfSight();
}

StepResult World::step(const CommandData& commands, double throttle, const TaskCounts& tasks) {
  const std::size_t n = robots_.size();
  if (commands.first_id != 0 || commands.size() != n)
    throw std::invalid_argument("World::step needs commands for all " + std::to_string(n) + " robots");
  ensureGrid();
  std::fill(robots_.events.begin(), robots_.events.end(), 0);
  StepResult result;
  const auto [served_pickup, served_drop] = servedBlockOps(commands);
  // Requests first, in id order: the lowest id wins a contested block.
  for (std::size_t i = 0; i < n; ++i) {
    const uint8_t req = commands.request[i];
    const double x = robots_.x[i], y = robots_.y[i];
    const auto robot = static_cast<int32_t>(i);
    int32_t& carried = robots_.carried[i];
    uint8_t& events = robots_.events[i];
    const uint8_t op =
        config_.serialize_block_ops ? serializedOp(static_cast<uint32_t>(i), req) : uint8_t{kNone};
    if ((op == kPickup && robot != served_pickup) || (op == kDrop && robot != served_drop))
      continue;  // its turn comes in a later tick: the request stands
    if (req == kPickup && carried < 0) {
      const int32_t b = blocks_.blockAt(x, y);
      if (b >= 0) {
        blocks_.pickUp(b, robot);
        carried = b;
        events |= kPickupDone;
      } else {
        events |= kBlockVanished;
      }
    } else if (req == kCachePickup && carried < 0) {
      const int32_t b = cache_.contains(x, y) ? cache_.take(blocks_, robot) : -1;
      if (b >= 0) {
        carried = b;
        events |= kPickupDone;
      } else {
        events |= kBlockVanished;
      }
    } else if (req == kDrop && carried >= 0) {
      if (config_.arena.nest().contains(x, y)) {
        blocks_.respawn(carried);
        ++result.delivered;
      } else {
        blocks_.putDown(carried, x, y);
      }
      carried = -1;
      events |= kDropDone;
    } else if (req == kCacheDrop && carried >= 0 && cache_.contains(x, y)) {
      cache_.put(blocks_, carried);  // a cache drop is not performance
      carried = -1;
      events |= kDropDone;
    }
  }
  if (config_.cache.enabled && !cache_.exists()) {
    CounterRng rng(config_.seed, RngStream::kCache, 0, tick_);
    if (rng.uniform() < cache_.recreationProbability(tasks.harvesters, tasks.collectors))
      cache_.create(blocks_);
  }
  const double scale = 1.0 - std::clamp(throttle, -1.0, 1.0);
  pushed_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double s = robots_.carried[i] >= 0 ? scale : 1.0;
    const double vmax = config_.robot.max_speed;
    move(static_cast<uint32_t>(i), std::clamp<double>(commands.left[i], -vmax, vmax) * s,
         std::clamp<double>(commands.right[i], -vmax, vmax) * s);
  }
  grid_valid_ = false;
  cumulative_ += result.delivered;
  ++tick_;
  return result;
}

std::pair<int32_t, int32_t> World::servedBlockOps(const CommandData& commands) {
  std::pair<int32_t, int32_t> served{-1, -1};
  if (!config_.serialize_block_ops) return served;
  uint64_t pickup_since = ~0ULL, drop_since = ~0ULL;
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    const uint8_t req = commands.request[i];
    if (req != robots_.last_request[i]) robots_.request_since[i] = tick_;
    robots_.last_request[i] = req;
    const uint64_t since = robots_.request_since[i];
    const uint8_t op = serializedOp(static_cast<uint32_t>(i), req);
    if (op == kPickup && since < pickup_since) {
      pickup_since = since;
      served.first = static_cast<int32_t>(i);
    } else if (op == kDrop && since < drop_since) {
      drop_since = since;
      served.second = static_cast<int32_t>(i);
    }
  }
  return served;
}

uint8_t World::serializedOp(uint32_t i, uint8_t request) const {
  const double x = robots_.x[i], y = robots_.y[i];
  const bool carrying = robots_.carried[i] >= 0;
  if (request == kPickup && !carrying && blocks_.blockAt(x, y) >= 0) return kPickup;
  if (request == kDrop && carrying && config_.arena.nest().contains(x, y)) return kDrop;
  return kNone;
}

void World::setPose(uint32_t i, double x, double y, double theta) {
  robots_.x.at(i) = x;
  robots_.y.at(i) = y;
  robots_.theta.at(i) = wrapAngle(theta);
  grid_valid_ = false;
}

void World::move(uint32_t i, double left, double right) {
  const RobotConfig& rc = config_.robot;
  const double dt = config_.dt();
  const double v = 0.5 * (left + right), w = (right - left) / rc.axle;
  const double th = robots_.theta[i];
  const double mid = th + 0.5 * w * dt;
  robots_.theta[i] = wrapAngle(th + w * dt);
  const double r = rc.radius;
  const double x0 = robots_.x[i], y0 = robots_.y[i];
  const double dx = v * std::cos(mid) * dt, dy = v * std::sin(mid) * dt;
  const auto inside = [&](double x, double y) {  // each axis on its own: bodies slide along walls
    return std::make_pair(std::clamp(x, r, config_.arena.width - r),
                          std::clamp(y, r, config_.arena.height - r));
  };
  const auto tryMove = [&](double mx, double my) {  // taken only if it keeps every body apart
    const auto [x, y] = inside(x0 + mx, y0 + my);
    if (!fits(i, x, y)) return false;
    robots_.x[i] = x;
    robots_.y[i] = y;
    return true;
  };
  if (tryMove(dx, dy)) return;
  // Blocked: slide along the contact, as a body in ARGoS' physics slips past the one it touches (the walls
  // already slide: each axis is clamped on its own). Without it, crowds lock up at the nest edge.
  const int32_t j = blocker(i, x0 + dx, y0 + dy);
  if (j >= 0 && !pushed_[j]) {
    // Push the blocker along the line of centres by half the move's component into it (equal bodies
    // share it), once per tick, if it has room: a crowd driving into another flows, as in ARGoS.
    double nx = robots_.x[j] - x0, ny = robots_.y[j] - y0;
    const double nlen = std::hypot(nx, ny);
    const double into = nlen > 1e-12 ? (dx * nx + dy * ny) / nlen : 0.0;
    if (into > 0) {
      nx /= nlen;
      ny /= nlen;
      const auto [jx, jy] = inside(robots_.x[j] + 0.5 * into * nx, robots_.y[j] + 0.5 * into * ny);
      if (fits(static_cast<uint32_t>(j), jx, jy)) {
        robots_.x[j] = jx;
        robots_.y[j] = jy;
        pushed_[j] = 1;
        if (tryMove(dx, dy)) return;
      }
    }
  }
  if (j >= 0) {
    double tx = -(robots_.y[j] - y0), ty = robots_.x[j] - x0;  // perpendicular to the line of centres
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
    const double ex = robots_.x[j] - x, ey = robots_.y[j] - y, e2 = ex * ex + ey * ey;
    if (e2 < best) {
      best = e2;
      nearest = static_cast<int32_t>(j);
    }
  });
  return nearest;
}

bool World::overlapFree() const {
  const double r = config_.robot.radius, W = config_.arena.width, H = config_.arena.height;
  UniformGrid g(W, H, 2 * r + 0.01);
  g.build(robots_.x.data(), robots_.y.data(), robots_.size());
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    const double x = robots_.x[i], y = robots_.y[i];
    if (x < r - 1e-12 || y < r - 1e-12 || x > W - r + 1e-12 || y > H - r + 1e-12) return false;
    bool ok = true;
    g.forNeighbours(x, y, [&](uint32_t j) {
      if (j == i) return;
      const double dx = robots_.x[j] - x, dy = robots_.y[j] - y;
      if (dx * dx + dy * dy < 4 * r * r) ok = false;
    });
    if (!ok) return false;
  }
  return true;
}

}  // namespace swarm_forage
