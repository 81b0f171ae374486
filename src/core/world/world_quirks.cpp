// FORDYCA 2019's world-side quirks (docs/FIDELITY.md, "FORDYCA as it ran", (6)-(8)), each switched by
// WorldConfig::quirks: the rim ground sensors, the block operation penalties and the light occlusion.
#include <algorithm>
#include <cmath>

#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

uint8_t World::rimGroundFor(double x, double y, double th) const {
  // Where no sensor can reach the nest, the cache or a block, all four read the floor: no trigonometry.
  const double x0 = x - kMotorGroundReach, x1 = x + kMotorGroundReach;
  const double y0 = y - kMotorGroundReach, y1 = y + kMotorGroundReach;
  const auto apart = [&](const Rect& r) {
    return x1 < r.min_x || x0 > r.max_x || y1 < r.min_y || y0 > r.max_y;
  };
  if (apart(nest_) && (!cache_.exists() || apart(cache_.area())) && !blocks_.mayHoldBlock(x0, y0, x1, y1))
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

bool World::lightShadowed(uint32_t self, int l) const {
  const double x = sx_[self], y = sy_[self];
  const double lx = lights_[l].x(), ly = lights_[l].y(), lz = kFordycaLightHeight[l];
  const double dx = lx - x, dy = ly - y, d = std::sqrt(dx * dx + dy * dy);
  if (d < 1e-12) return false;
  const double r = config_.robot.radius;
  const uint32_t* const order = grid_.order().data();
  const uint32_t* const rank = grid_.rank().data();
  const uint32_t placed = grid_.placed();
  // The body that shadowed this light last tick most often still does (bodies move little in a tick):
  // one exact test instead of a walk. Only the answer counts, never which body gave it, so the cache
  // changes no result.
  uint32_t& witness = shadow_witness_[static_cast<std::size_t>(order[self]) * ArenaConfig::kLights + l];
  if (witness != kNoWitness) {
    const uint32_t k = rank[witness];
    if (k < placed && k != self && footBotShadows(x, y, lx, ly, lz, sx_[k], sy_[k], sth_[k], r)) return true;
  }
  // Only a body entered within shadowReach of the robot (seen from above) is low enough to cut the ray:
  // the cells of shadow_grid_ along that stretch, widened by a body's reach (its disc and its gripper). The
  // bounds below only choose which bodies get the exact test; pad's 1e-9 covers their roundings.
  const double t_max = std::min(1.0, shadowReach(d, lz) / d);
  const double ex = x + t_max * dx, ey = y + t_max * dy;
  const UniformGrid& grid = shadow_grid_;
  const uint32_t* const slot_of = grid.order().data();  // its points are slots
  const double pad = r + kGripperRadius + 1e-9, cell = grid.cellSize(), inv_cell = 1.0 / cell;
  const double inv_d = 1.0 / d, ux = dx * inv_d, uy = dy * inv_d, reach = t_max * d + pad;
  uint32_t hit = kNoWitness;
  const auto test = [&](uint32_t p) {
    const uint32_t k = slot_of[p];
    if (hit != kNoWitness || k == self) return;
    // A cheap bound first: every part of a body lies within `pad` of its centre.
    const double ox = sx_[k] - x, oy = sy_[k] - y, along = ox * ux + oy * uy;
    if (along < 0 || along > reach || std::abs(ox * uy - oy * ux) > pad) return;
    if (footBotShadows(x, y, lx, ly, lz, sx_[k], sy_[k], sth_[k], r)) hit = k;
  };
  // From the robot outward, one grid line across the stretch's main direction at a time: in a crowd a
  // body near the robot shadows it, and the walk ends there. A line's cells are those of the stretch's
  // part within pad of the line, widened by pad.
  const bool by_column = std::abs(ex - x) >= std::abs(ey - y);
  const double a0 = by_column ? x : y, a1 = by_column ? ex : ey;  // along the main axis
  const double b0 = by_column ? y : x, b1 = by_column ? ey : ex;  // across it
  const int n_a = by_column ? grid.columns() : grid.rows(), n_b = by_column ? grid.rows() : grid.columns();
  const auto cellOf = [inv_cell](double v, int n) {
    return std::clamp(static_cast<int>(v * inv_cell), 0, n - 1);
  };
  const double sa = a1 - a0, slope = std::abs(sa) > 1e-12 ? (b1 - b0) / sa : 0.0;
  const double a_lo = std::min(a0, a1), a_hi = std::max(a0, a1);
  const int step = sa >= 0 ? 1 : -1;
  const int first = cellOf(a0 - step * pad, n_a), last = cellOf(a1 + step * pad, n_a);
  for (int g = first;; g += step) {
    // The stretch's part within pad of line g, and its extent across.
    const double ua = std::clamp(g * cell - pad, a_lo, a_hi),
                 ub = std::clamp((g + 1) * cell + pad, a_lo, a_hi);
    const double ba = b0 + (ua - a0) * slope, bb = b0 + (ub - a0) * slope;
    const int h0 = cellOf(std::min(ba, bb) - pad, n_b), h1 = cellOf(std::max(ba, bb) + pad, n_b);
    if (by_column) {
      for (int gy = h0; gy <= h1; ++gy) grid.forRow(gy, g, g, test);
    } else {
      grid.forRow(g, h0, h1, test);
    }
    if (hit != kNoWitness || g == last) break;
  }
  witness = hit == kNoWitness ? kNoWitness : order[hit];
  return hit != kNoWitness;
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
