#include "swarm_forage/core/world/fordyca_world_quirks.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

uint8_t rimGround(const uint8_t kinds[kMotorGroundSensors]) {
  int black = 0, nest = 0, cache = 0;
  for (int k = 0; k < kMotorGroundSensors; ++k) {
    black += kinds[k] == kBlockGround;
    nest += kinds[k] == kNest;
    cache += kinds[k] == kCacheGround;
  }
  // sensing_subsystem: block_detected detect(0.0, 0.05, 4); in_nest detect(0.7, 0.1, 3); cache_detected
  // detect(0.4, 0.1, 3). The floor's grey levels (black 0, nest 179/255, cache 102/255, white 1) fall in
  // one window each, so the three cannot hold at once.
  if (black == kMotorGroundSensors) return kBlockGround;
  if (nest >= 3) return kNest;
  if (cache >= 3) return kCacheGround;
  return kFloor;
}

bool rayEntersBody(double x, double y, double lx, double ly, double lz, double cx, double cy, double r) {
  // chipmunk's circleSegmentQuery, relative to the circle's centre.
  const double ax = x - cx, ay = y - cy, bx = lx - cx, by = ly - cy;
  const double a_a = ax * ax + ay * ay, a_b = ax * bx + ay * by, b_b = bx * bx + by * by;
  const double qa = a_a - 2 * a_b + b_b, qb = -2 * a_a + 2 * a_b, qc = a_a - r * r;
  const double det = qb * qb - 4 * qa * qc;
  if (det < 0 || qa <= 0) return false;
  const double t = (-qb - std::sqrt(det)) / (2 * qa);
  // In the segment, nearer than the light (ARGoS keeps hits with t < 1), and within the body's height.
  return t >= 0 && t < 1 && t * lz <= kFootBotHeight;
}

bool footBotShadows(double x, double y, double lx, double ly, double lz, double cx, double cy, double th,
                    double r) {
  if (rayEntersBody(x, y, lx, ly, lz, cx, cy, r)) return true;
  return rayEntersBody(x, y, lx, ly, lz, cx + r * std::cos(th), cy + r * std::sin(th), kGripperRadius);
}

void BlockPenaltyHandler::reset(std::size_t n_robots) {
  list_.clear();
  serving_.assign(n_robots, 0);
}

uint32_t BlockPenaltyHandler::deconflict(uint64_t tick, uint32_t value) const {
  uint64_t penalty = value == 0 ? 1 : value;
  // temporal_penalty_handler::deconflict_penalty_finish, as written: after a clash the iterator is reset to
  // begin() and then advanced by the loop, so the first entry is not looked at again.
  for (auto it = list_.begin(); it != list_.end(); ++it) {
    if (it->start + it->penalty == tick + penalty) {
      ++penalty;
      it = list_.begin();
    }
  }
  return static_cast<uint32_t>(penalty);
}

void BlockPenaltyHandler::start(uint32_t robot, int32_t id, uint64_t tick, uint32_t value) {
  list_.push_back(Penalty{robot, id, deconflict(tick, value), tick});
  serving_[robot] = 1;
}

const BlockPenaltyHandler::Penalty& BlockPenaltyHandler::of(uint32_t robot) const {
  return *std::find_if(list_.begin(), list_.end(), [&](const Penalty& p) { return p.robot == robot; });
}

bool BlockPenaltyHandler::satisfied(uint32_t robot, uint64_t tick) const {
  if (!serving(robot)) return false;
  const Penalty& p = of(robot);
  return tick - p.start >= p.penalty;
}

void BlockPenaltyHandler::remove(uint32_t robot) {
  if (!serving(robot)) return;
  list_.erase(std::find_if(list_.begin(), list_.end(), [&](const Penalty& p) { return p.robot == robot; }));
  serving_[robot] = 0;
}

std::vector<uint32_t> argosIdOrder(uint32_t n) {
  std::vector<uint32_t> order(n);
  for (uint32_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [](uint32_t a, uint32_t b) { return std::to_string(a) < std::to_string(b); });
  return order;
}

}  // namespace swarm_forage
