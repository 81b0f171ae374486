// FORDYCA 2019's world-side quirks (docs/FIDELITY.md, "FORDYCA as it ran", (6)-(8)), each switched by
// WorldConfig::quirks: the rim ground sensors and the block operation penalties (the light occlusion is in
// light_occlusion.cpp).
#include <algorithm>
#include <cmath>
#include <cstring>

#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

static_assert(kMotorGroundReach < BlockField::kNearReach, "nearBlock covers the sensors' box");

uint8_t World::rimGroundFor(double x, double y, double th) const {
  // Where no sensor can reach the nest, the cache or a block's footprint, all four read the floor: no
  // trigonometry.
  const double x0 = x - kMotorGroundReach, x1 = x + kMotorGroundReach;
  const double y0 = y - kMotorGroundReach, y1 = y + kMotorGroundReach;
  const auto apart = [&](const Rect& r) {
    return x1 < r.min_x || x0 > r.max_x || y1 < r.min_y || y0 > r.max_y;
  };
  if (apart(nest_) && (!cache_.exists() || apart(cache_.area())) &&
      (!blocks_.nearBlock(x, y) || !blocks_.touchesBlock(x0, y0, x1, y1)))
    return kFloor;
  // Where all four are in the nest, they read the nest's grey (groundAt looks at the nest first).
  if (x0 >= nest_.min_x && x1 <= nest_.max_x && y0 >= nest_.min_y && y1 <= nest_.max_y) return kNest;
  // ARGoS' footbot_motor_ground_rotzonly_sensor: each sensor's offset rotated by the heading, plus the
  // centre; the floor's colour there (FORDYCA's GetFloorColor: nest, then cache, then blocks, else white).
  const double c = std::cos(th), s = std::sin(th);
  uint8_t kinds[kMotorGroundSensors];
  for (int k = 0; k < kMotorGroundSensors; ++k)
    kinds[k] = groundAt(x + c * kMotorGroundX[k] - s * kMotorGroundY[k],
                        y + s * kMotorGroundX[k] + c * kMotorGroundY[k]);
  return rimGround(kinds);
}

bool World::dropsInNest(std::size_t i) const {
  if (!config_.quirks.has(Quirk::kRimGroundSensors))
    return config_.arena.nest().contains(robots_.x[i], robots_.y[i]);
  return groundFor(robots_.x[i], robots_.y[i], robots_.theta[i]) == kNest;  // FORDYCA's in_nest()
}

void World::penaltyStep(const CommandData& commands, uint64_t value, StepResult& result) {
  const std::size_t n = robots_.size();
  penalised_.assign(n, 0);
  const uint8_t* mask = activeMask();
  const auto v = static_cast<uint32_t>(value);
  // FORDYCA's PreStep visits every foot-bot (ARGoS' id order) and hands it to the nest drop interactor
  // when it carries a block, else to the free pick-up interactor. Only a robot serving a penalty or asking
  // for a pick-up or a drop can change anything there (nor does any other's visit change that), so only
  // those are visited, in the same order.
  std::vector<uint32_t>& visit = penalty_visits_;
  visit.clear();
  const uint8_t* const request = commands.request.data();
  static_assert(kNone == 0, "8 zero request bytes are 8 robots without a request");
  for (std::size_t i = 0; i < n; ++i) {
    uint64_t eight;
    if (i % 8 == 0 && i + 8 <= n && (std::memcpy(&eight, request + i, sizeof eight), eight == 0)) {
      i += 7;
      continue;
    }
    if (request[i] == kPickup || request[i] == kDrop) visit.push_back(static_cast<uint32_t>(i));
  }
  for (const BlockPenaltyHandler* h : {&pickup_penalties_, &drop_penalties_})
    for (const BlockPenaltyHandler::Penalty& p : h->penalties()) visit.push_back(p.robot);
  std::sort(visit.begin(), visit.end(),
            [&](uint32_t a, uint32_t b) { return argos_rank_[a] < argos_rank_[b]; });
  visit.erase(std::unique(visit.begin(), visit.end()), visit.end());
  for (const uint32_t i : visit) {
    const uint8_t req = commands.request[i];
    int32_t& carried = robots_.carried[i];
    if (mask && !mask[i]) {  // out of the swarm: no penalty stands for it
      pickup_penalties_.remove(i);
      drop_penalties_.remove(i);
      continue;
    }
    const double x = robots_.x[i], y = robots_.y[i];
    BlockPenaltyHandler& h = carried >= 0 ? drop_penalties_ : pickup_penalties_;
    const uint8_t op = carried >= 0 ? kDrop : kPickup;
    (carried >= 0 ? pickup_penalties_ : drop_penalties_).remove(i);  // the other operation is over
    if (h.serving(i) && req != op) {
      h.remove(i);  // the controller gave up waiting (penalty_abort)
      continue;
    }
    if (h.serving(i)) {
      penalised_[i] = 1;  // waits: the request stands
      if (!h.satisfied(i, tick_)) continue;
      const BlockPenaltyHandler::Penalty p = h.of(i);
      h.remove(i);
      if (op == kPickup) {
        // free_block_pickup_interactor: the block it served the penalty for must still be under it.
        if (blocks_.blockAt(x, y) == p.id) {
          blocks_.pickUp(p.id, static_cast<int32_t>(i));
          carried = p.id;
          robots_.events[i] |= kPickupDone;
        } else {
          robots_.events[i] |= kBlockVanished;
        }
      } else {  // nest_block_drop_interactor: the drop counts, wherever the robot was pushed meanwhile
        blocks_.respawn(carried);
        ++result.delivered;
        carried = -1;
        robots_.events[i] |= kDropDone;
      }
      continue;
    }
    // block_op_filter, then penalty_init.
    if (op == kPickup && req == kPickup) {
      const int32_t b = blocks_.blockAt(x, y);
      if (b < 0) continue;  // not on a block: the world answers the request as without the quirk
      h.start(i, b, tick_, v);
      penalised_[i] = 1;
    } else if (op == kDrop && req == kDrop && dropsInNest(i)) {
      h.start(i, carried, tick_, v);
      penalised_[i] = 1;
    }
  }
}

}  // namespace swarm_forage
