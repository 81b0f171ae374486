#include "swarm_forage/core/world/world.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "swarm_forage/core/util/rng.hpp"

namespace swarm_forage {

namespace {
// Requests are rare (kNone is 0): the request loops skip 8 robots at a time where robot i starts 8 whose
// bytes in `a` equal those in `b` (or are all kNone when `b` is null).
static_assert(kNone == 0, "the request loops skip 8 zero bytes as 8 robots without a request");
inline bool eightAlike(std::size_t i, std::size_t n, const uint8_t* a, const uint8_t* b = nullptr) {
  if (i % 8 != 0 || i + 8 > n) return false;
  uint64_t u, v = 0;
  std::memcpy(&u, a + i, sizeof u);
  if (b) std::memcpy(&v, b + i, sizeof v);
  return u == v;
}

// A 3x3 query must reach the threat distance, and a neighbour's tick-start cell even after it moved
// this tick (at most 2 x max_speed x dt, a fully boosted carrier).
double gridCell(const WorldConfig& c) {
  const RobotConfig& r = c.robot;
  return 2 * r.radius + std::max(r.threat_distance, 2 * r.max_speed * c.dt()) + 0.01;
}

// light_occlusion's bit per cell of the neighbour grid.
double shadowBitsBytes(double width, double height, double cell) {
  return (std::floor(std::max(1.0, std::ceil(width / cell)) * std::max(1.0, std::ceil(height / cell)) / 64) +
          2) *
         8;
}

}  // namespace

double WorldConfig::gridBytes() const {
  return UniformGrid::bytesFor(arena.width, arena.height, gridCell(*this)) + BlockField::gridBytes(arena) +
         (line_of_sight ? SightIndex::maskBytes(sight, arena) : 0.0) +
         (quirks.has(Quirk::kLightOcclusion) ? shadowBitsBytes(arena.width, arena.height, gridCell(*this))
                                             : 0.0);
}

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
  nest_ = config_.arena.nest();
  tick_ = 0;
  cumulative_ = 0;
  grid_ = UniformGrid(config_.arena.width, config_.arena.height, gridCell(config_));
  band_rows_ = bandRows(config_, grid_.cellSize());
  shadow_bits_.clear();  // sense() lays them out for light_occlusion
  dt_ = config_.dt();
  for (int l = 0; l < ArenaConfig::kLights; ++l) lights_[l] = config_.arena.light(l);
  blocks_.init(config_.arena, seed);
  cache_.init(config_.arena, config_.cache);
  if (config_.cache.enabled) cache_.create(blocks_);
  placeRobots();
  population_.reset(config_.population, seed, n_robots);
  pickup_penalties_.reset(n_robots);
  drop_penalties_.reset(n_robots);
  argos_rank_.clear();
  if (config_.quirks.has(Quirk::kBlockPenalties)) {
    const std::vector<uint32_t> order = argosIdOrder(n_robots);
    argos_rank_.resize(n_robots);
    for (uint32_t k = 0; k < n_robots; ++k) argos_rank_[order[k]] = k;
  }
  shadowed_lights_ = 0;
}

void World::placeRobots() {
  const uint32_t n = config_.n_robots;
  robots_.x.assign(n, 0);
  robots_.y.assign(n, 0);
  robots_.theta.assign(n, 0);
  sx_.assign(n, 0);
  sy_.assign(n, 0);
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
      robots_.x[i] = sx_[i] = x;  // while placing, slot = id
      robots_.y[i] = sy_[i] = y;
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

void World::setThreads(unsigned threads) {
  if (threads == 0) threads = WorkerPool::cores();
  if (threads != pool_->threads()) pool_ = std::make_shared<WorkerPool>(threads);
}

void World::ensureGrid() {
  if (grid_valid_) return;
  buildGrid();
  slotGrid();
}

void World::slotGrid() {
  copyToSlots();
  grid_valid_ = true;
  clearance_valid_ = false;
}

uint32_t World::carrying() const {
  return static_cast<uint32_t>(
      std::count_if(robots_.carried.begin(), robots_.carried.end(), [](int32_t b) { return b >= 0; }));
}

StepResult World::step(const CommandData& commands, Throttling throttle, const TaskCounts& tasks) {
  const std::size_t n = robots_.size();
  if (commands.first_id != 0 || commands.size() != n)
    throw std::invalid_argument("World::step needs commands for all " + std::to_string(n) + " robots");
  ensureGrid();
  std::fill(robots_.events.begin(), robots_.events.end(), 0);
  StepResult result;
  const double v = std::clamp(throttle.value, -1.0, 1.0);
  // manipulation_time: a block operation finishes once requested for this many ticks (0: at once).
  const uint64_t hold =
      throttle.target != ConditionTarget::kManipulationTime
          ? 0
          : static_cast<uint64_t>(
                std::ceil(std::max(0.0, v) * kMaxManipulationSeconds * config_.ticks_per_second - 1e-9));
  trackRequests(commands);
  const auto [served_pickup, served_drop] = servedBlockOps(commands);
  // block_penalties: FORDYCA's penalty handlers take the free pick-ups and nest drops (world_quirks.cpp),
  // with the manipulation time as their penalty; they replace serialize_block_ops.
  const bool penalties = config_.quirks.has(Quirk::kBlockPenalties);
  if (penalties) penaltyStep(commands, hold, result);
  const uint8_t* mask = activeMask();
  // Requests first, in id order: the lowest id wins a contested block.
  for (std::size_t i = 0; i < n; ++i) {
    if (eightAlike(i, n, commands.request.data())) {  // no request (kNone) for 8 robots: nothing
      i += 7;
      continue;
    }
    if (mask && !mask[i]) continue;            // out of the swarm: whatever a controller sent is not executed
    if (penalties && penalised_[i]) continue;  // serving its penalty, or its operation done this tick
    const uint8_t req = commands.request[i];
    const double x = robots_.x[i], y = robots_.y[i];
    const auto robot = static_cast<int32_t>(i);
    int32_t& carried = robots_.carried[i];
    uint8_t& events = robots_.events[i];
    const uint8_t op = config_.serialize_block_ops && !penalties ? serializedOp(static_cast<uint32_t>(i), req)
                                                                 : uint8_t{kNone};
    if ((op == kPickup && robot != served_pickup) || (op == kDrop && robot != served_drop))
      continue;  // its turn comes in a later tick: the request stands
    if (hold > 0 && req != kNone && tick_ - robots_.request_since[i] < hold)
      continue;  // still picking up or dropping: the request stands
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
      if (dropsInNest(i)) {
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
  const double scale = throttle.target == ConditionTarget::kManipulationTime ? 1.0 : 1.0 - v;
  moveAll(config_.noise.wheels.on() ? wheelNoise(commands) : commands, scale,
          throttle.target == ConditionTarget::kSpeed ? scale : 1.0);
  if (population_.enabled()) populationStep();
  grid_valid_ = false;
  cumulative_ += result.delivered;
  ++tick_;
  return result;
}

const CommandData& World::wheelNoise(const CommandData& commands) {
  // The world applies it, so every controller (in process, nodes, plugins, rospy) gets the same noise, and
  // the commands a controller sent stay what it asked.
  noisy_commands_.left = commands.left;
  noisy_commands_.right = commands.right;
  for (std::size_t i = 0; i < noisy_commands_.left.size(); ++i)
    config_.noise.perturbWheels(noisy_commands_.left[i], noisy_commands_.right[i], static_cast<uint32_t>(i),
                                config_.seed, tick_, config_.robot.max_speed);
  return noisy_commands_;
}

void World::setNoise(const SaaNoise& noise) {
  noise.validate();
  config_.noise = noise;
}

void World::trackRequests(const CommandData& commands) {
  const std::size_t n = robots_.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (eightAlike(i, n, commands.request.data(), robots_.last_request.data())) {
      i += 7;  // 8 requests as last tick: nothing to record
      continue;
    }
    const uint8_t req = commands.request[i];
    if (req != robots_.last_request[i]) robots_.request_since[i] = tick_;
    robots_.last_request[i] = req;
  }
}

std::pair<int32_t, int32_t> World::servedBlockOps(const CommandData& commands) {
  std::pair<int32_t, int32_t> served{-1, -1};
  if (!config_.serialize_block_ops || config_.quirks.has(Quirk::kBlockPenalties)) return served;
  uint64_t pickup_since = ~0ULL, drop_since = ~0ULL;
  const uint8_t* mask = activeMask();
  const std::size_t n = robots_.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (eightAlike(i, n, commands.request.data())) {  // kNone serves nothing
      i += 7;
      continue;
    }
    if (mask && !mask[i]) continue;
    const uint8_t req = commands.request[i];
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
  if (request == kDrop && carrying && dropsInNest(i)) return kDrop;
  return kNone;
}

void World::setPose(uint32_t i, double x, double y, double theta) {
  robots_.x.at(i) = x;
  robots_.y.at(i) = y;
  robots_.theta.at(i) = wrapAngle(theta);
  grid_valid_ = false;
}

bool World::overlapFree() const {
  const double r = config_.robot.radius, W = config_.arena.width, H = config_.arena.height;
  UniformGrid g(W, H, 2 * r + 0.01);
  g.build(robots_.x.data(), robots_.y.data(), robots_.size(), activeMask());
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    if (!active(i)) continue;
    const double x = robots_.x[i], y = robots_.y[i];
    if (x < r - 1e-12 || y < r - 1e-12 || x > W - r + 1e-12 || y > H - r + 1e-12) return false;
    bool ok = true;
    g.forNeighbours(x, y, [&](uint32_t k) {
      const uint32_t j = g.order()[k];
      if (j == i) return;
      const double dx = robots_.x[j] - x, dy = robots_.y[j] - y;
      if (dx * dx + dy * dy < 4 * r * r) ok = false;
    });
    if (!ok) return false;
  }
  return true;
}

}  // namespace swarm_forage
