#include "swarm_forage/core/controllers/crw.hpp"

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/util/rng.hpp"

namespace swarm_forage {

namespace {
const std::vector<std::string>& stateNames() {
  static const std::vector<std::string> names = {"explore",     "pickup", "transport",
                                                 "nest_wander", "drop",   "leave_nest"};
  return names;
}
}  // namespace

const char* crwStateName(CrwState s) { return stateNames()[static_cast<std::size_t>(s)].c_str(); }

void visitCrwParameters(CrwConfig& c, ConstantVisitor& v) {
  v.degrees("wander_step_deg", c.wander_step);
  v.degrees("wander_limit_deg", c.wander_limit);
  v.number("wander_circle_distance", c.wander_circle_distance);
  v.number("wander_circle_radius", c.wander_circle_radius);
  v.number("wander_force", c.wander_force);
  v.number("wander_free_scale", c.wander_free_scale);
  v.number("avoidance_force", c.avoidance_force);
  v.number("phototaxis_force", c.phototaxis_force);
  v.count("nest_wander_ticks", c.nest_wander_ticks);
  v.count("min_explore_ticks", c.min_explore_ticks);
  v.number("max_speed", c.drive.max_speed);
  v.degrees("soft_turn_max_deg", c.drive.soft_turn_max);
  v.number("hard_turn_speed", c.drive.hard_turn_speed);
}

namespace {
ControllerKind crwKind() {
  ControllerKind k;
  k.name = "crw";
  k.light_only_carrying = true;  // phototaxis in transport only
  k.display_name = "CRW";
  k.colour = "tab:blue";
  k.defaults = "config/controllers/crw.yaml";
  k.constants = sectionOf(visitCrwParameters);
  k.make = [](const ControllerConfigs& c, uint32_t seed, uint32_t first_id, uint32_t count) {
    CrwConfig config = c.of<CrwConfig>("crw");
    config.quirks = c.quirks.controllerSide();
    return std::make_unique<CrwBatch>(config, seed, first_id, count);
  };
  return k;
}
const ControllerRegistrar registrar{crwKind()};
}  // namespace

CrwBatch::CrwBatch(const CrwConfig& config, uint32_t seed, uint32_t first_id, uint32_t count)
    : ForagerBatch(seed, first_id, count), config_(config) {
  wander_at_tick_ = true;
  config_.validate();
  quirks_ = config_.quirks.controllerSide();
}

void CrwBatch::step(uint64_t tick, const SensorData& s, CommandData& out, ControllerStatus& status) {
  prepare(out, status, stateNames());
  beginDrives();
  driveAll(tick, s, config_, out, status);  // chooseDrives() per strip, then the strip's drives
}

void CrwBatch::chooseDrives(uint32_t first, uint32_t end, uint64_t /*tick*/, const SensorData& s,
                            CommandData& out) {
  // Transitions, requests, and which robots wander this tick (and draw). Arrays through local pointers:
  // the byte stores would otherwise make the compiler reload each vector's data pointer per robot.
  uint8_t *const state_of = state_.data(), *const request = request_.data(), *const slow = slow_.data(),
                 *const motion = motion_.data();
  uint32_t* const ticks = state_ticks_.data();
  Vec2* const force = force_.data();
  const uint8_t *const grounds = s.ground.data(), *const all_events = s.events.data();
  const int32_t* const carried = s.carried_block.data();
  uint32_t* const wanders = wanders_.data();
  uint32_t wandering = wander_count_;
  for (uint32_t l = first; l < end; ++l) {
    if (idle(l, s, out)) {
      request[l] = kStill;
      continue;
    }
    const uint32_t i = first_id_ + l;
    const uint8_t ground = grounds[i], events = all_events[i];
    const bool carrying = carried[i] >= 0;
    auto state = static_cast<CrwState>(state_of[l]);
    // Transitions driven by what the world executed and what the robot stands on.
    switch (state) {
      case CrwState::kExplore:
        if (ground == kBlockGround && !carrying && ticks[l] >= config_.min_explore_ticks)
          state = CrwState::kPickup;  // the tick count carries over, see kPickup
        break;
      case CrwState::kPickup:
        if (carrying || (events & kPickupDone)) {
          state = CrwState::kTransport;
          ticks[l] = 0;
        } else if (ground != kBlockGround) {
          state = CrwState::kExplore;  // keeps its exploration time
        }
        break;
      default:
        if (deliveryTransition(state, ticks[l], ground, carrying, events, config_.nest_wander_ticks))
          ticks[l] = 0;
        break;
    }
    state_of[l] = static_cast<uint8_t>(state);
    // Actions of the state the robot is now in.
    request[l] = kNone;
    Motion m = Motion::kExplore;
    slow[l] = 0;
    switch (state) {
      case CrwState::kPickup:
        request[l] = kPickup;  // stopped on the block
        continue;
      case CrwState::kDrop:
        request[l] = kDrop;
        continue;
      case CrwState::kTransport:
        m = Motion::kTransport;
        slow[l] = nearlyStopped(l, i, s) ? 1 : 0;
        break;
      case CrwState::kNestWander:
        m = Motion::kNestWander;
        break;
      case CrwState::kLeaveNest:
        m = Motion::kLeaveNest;
        break;
      default:
        break;
    }
    motion[l] = static_cast<uint8_t>(m);
    force[l] = Vec2(0, 0);
    if (motionWanders(m, s, i, slow[l] != 0))
      wanders[wandering++] = l;  // its only draw of the tick: driveAll takes it (wander_at_tick_)
  }
  wander_count_ = wandering;
}

}  // namespace swarm_forage
