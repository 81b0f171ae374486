// FORDYCA 2019's world-side quirks (docs/FIDELITY.md, "FORDYCA as it ran", (6)-(8)), each switched by
// WorldConfig::quirks: the rim ground sensors, the block operation penalties and the light occlusion.
#include <algorithm>
#include <cmath>

#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

uint8_t World::rimGroundFor(double x, double y, double th) const {
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

bool World::lightShadowed(uint32_t self, int l) const {
  const double x = sx_[self], y = sy_[self];
  const double lx = lights_[l].x(), ly = lights_[l].y(), lz = kFordycaLightHeight[l];
  const double dx = lx - x, dy = ly - y, d = std::sqrt(dx * dx + dy * dy);
  if (d < 1e-12) return false;
  // Only a body entered within shadowReach of the robot (seen from above) is low enough to cut the ray:
  // scan the grid cells along that stretch, widened by a body's reach (its disc and its gripper).
  const double t_max = std::min(1.0, shadowReach(d, lz) / d);
  const double ex = x + t_max * dx, ey = y + t_max * dy;
  const double r = config_.robot.radius, pad = r + kGripperRadius + 1e-9, cell = grid_.cellSize();
  const double ux = dx / d, uy = dy / d, reach = t_max * d + pad;
  bool hit = false;
  const auto test = [&](uint32_t k) {
    if (hit || k == self) return;
    // A cheap bound first: every part of a body lies within `pad` of its centre.
    const double ox = sx_[k] - x, oy = sy_[k] - y, along = ox * ux + oy * uy;
    if (along < 0 || along > reach || std::abs(ox * uy - oy * ux) > pad) return;
    if (footBotShadows(x, y, lx, ly, lz, sx_[k], sy_[k], sth_[k], r)) hit = true;
  };
  // Row by row of grid cells, the columns the widened stretch covers in that row (one range of sorted
  // positions when the grid lays out every cell).
  const double y_lo = std::min(y, ey) - pad, y_hi = std::max(y, ey) + pad, sy = ey - y;
  for (int gy = grid_.cellY(y_lo), gy_end = grid_.cellY(y_hi); gy <= gy_end && !hit; ++gy) {
    const double ya = std::max(y_lo, gy * cell) - pad, yb = std::min(y_hi, (gy + 1) * cell) + pad;
    double u0 = 0, u1 = 1;  // the stretch's part within pad of the row
    if (std::abs(sy) > 1e-12) {
      u0 = std::clamp((ya - y) / sy, 0.0, 1.0);
      u1 = std::clamp((yb - y) / sy, 0.0, 1.0);
    }
    const double xa = x + u0 * (ex - x), xb = x + u1 * (ex - x);
    grid_.forRow(gy, grid_.cellX(std::min(xa, xb) - pad), grid_.cellX(std::max(xa, xb) + pad), test);
  }
  return hit;
}

void World::penaltyStep(const CommandData& commands, uint64_t value, StepResult& result) {
  const std::size_t n = robots_.size();
  penalised_.assign(n, 0);
  const uint8_t* mask = activeMask();
  const auto v = static_cast<uint32_t>(value);
  // FORDYCA's PreStep visits every foot-bot (ARGoS' id order) and hands it to the nest drop interactor
  // when it carries a block, else to the free pick-up interactor.
  for (const uint32_t i : argos_order_) {
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
