#include "swarm_forage/core/controllers/dpo.hpp"

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/util/rng.hpp"

namespace swarm_forage {

void DpoConfig::validate() const {
  const auto require = requireParameter;
  explore.validate();
  require(std::isfinite(nest_center.x()) && std::isfinite(nest_center.y()), "dpo/nest_center must be finite");
  require(los_cell > 0 && los_cell <= 10, "dpo/los_cell must be in (0, 10] m");
  require(los_radius >= 0 && los_radius <= 100, "dpo/los_radius must be in [0, 100] cells");
  require(pheromone_initial >= 0 && pheromone_initial <= 100, "dpo/pheromone_initial must be in [0, 100]");
  require(pheromone_decay >= 0 && pheromone_decay < 1, "dpo/pheromone_decay must be in [0, 1)");
  require(new_place_distance >= 0 && new_place_distance <= 10, "dpo/new_place_distance must be in [0, 10] m");
  require(exclusion_radius >= 0 && exclusion_radius <= 10, "dpo/exclusion_radius must be in [0, 10] m");
  require(arrival_tolerance > 0 && arrival_tolerance <= 1, "dpo/arrival_tolerance must be in (0, 1] m");
  require(slowing_radius >= 0 && slowing_radius <= 10, "dpo/slowing_radius must be in [0, 10] m");
  require(vector_force > 0 && vector_force <= 100, "dpo/vector_force must be in (0, 100] cm/s");
  require(collision_window <= 1000000, "dpo/collision_window must be in [0, 1000000] ticks");
  require(recovery_spin_ticks <= 1000, "dpo/recovery_spin_ticks must be in [0, 1000]");
  require(recovery_spin_speed > 0 && recovery_spin_speed <= 1, "dpo/recovery_spin_speed must be in (0, 1]");
  require(recovery_max_offset >= 0 && recovery_max_offset <= kPi,
          "dpo/recovery_max_offset must be in [0, pi] rad");
  require(recovery_heading_tolerance > 0 && recovery_heading_tolerance <= kPi,
          "dpo/recovery_heading_tolerance must be in (0, pi] rad");
  require(slowing_speed_min >= 0 && slowing_speed_min <= vector_force,
          "dpo/slowing_speed_min must be in [0, vector_force] cm/s");
  require(recovery_straight_ticks <= 1000, "dpo/recovery_straight_ticks must be in [0, 1000]");
  require(recovery_straight_speed > 0 && recovery_straight_speed <= 1,
          "dpo/recovery_straight_speed must be in (0, 1]");
}

namespace {
ControllerKind dpoKind() {
  ControllerKind k;
  k.name = "dpo";
  k.light_only_carrying = true;  // phototaxis in transport only
  k.display_name = "DPO";
  k.colour = "tab:orange";
  k.defaults = "config/controllers/dpo.yaml";
  k.builds_on = "crw";
  k.line_of_sight = true;
  k.constants = sectionOf(visitDpoParameters);
  k.make = [](const ControllerConfigs& c, uint32_t seed, uint32_t first_id, uint32_t count) {
    return std::make_unique<DpoBatch>(dpoConfig(c), seed, first_id, count);
  };
  return k;
}
const ControllerRegistrar registrar{dpoKind()};
}  // namespace

const std::vector<std::string>& dpoStateNames() {
  static const std::vector<std::string> names = {"explore",     "vector", "pickup",    "transport",
                                                 "nest_wander", "drop",   "leave_nest"};
  return names;
}

const char* dpoStateName(DpoState s) { return dpoStateNames()[static_cast<std::size_t>(s)].c_str(); }

void visitDpoParameters(DpoConfig& c, ConstantVisitor& v) {
  v.number("pheromone_initial", c.pheromone_initial);
  v.number("pheromone_decay", c.pheromone_decay);
  v.number("new_place_distance", c.new_place_distance);
  v.number("exclusion_radius", c.exclusion_radius);
  v.number("arrival_tolerance", c.arrival_tolerance);
  v.number("slowing_radius", c.slowing_radius);
  v.number("vector_force", c.vector_force);
  v.number("slowing_speed_min", c.slowing_speed_min);
  v.count("collision_window", c.collision_window);
  v.number("recovery_max_offset", c.recovery_max_offset);
  v.number("recovery_heading_tolerance", c.recovery_heading_tolerance);
  v.count("recovery_spin_ticks", c.recovery_spin_ticks);
  v.number("recovery_spin_speed", c.recovery_spin_speed);
  v.count("recovery_straight_ticks", c.recovery_straight_ticks);
  v.number("recovery_straight_speed", c.recovery_straight_speed);
}

DpoConfig dpoConfig(const ControllerConfigs& configs) {
  DpoConfig c = configs.of<DpoConfig>("dpo");
  c.explore = configs.of<CrwConfig>("crw");
  c.explore.quirks = configs.quirks.controllerSide();
  if (configs.world) {
    c.nest_center = configs.world->nest_center;
    c.los_cell = configs.world->sight.cell;
    c.los_radius = configs.world->sight.radius;
  }
  return c;
}

DpoBatch::DpoBatch(const DpoConfig& config, uint32_t seed, uint32_t first_id, uint32_t count)
    : ForagerBatch(seed, first_id, count),
      config_(config),
      los_(config.lineOfSight()),
      pheromone_(config.pheromone()),
      blocks_(count),
      target_(count, -1),
      last_collision_(count, kNever),
      recovery_phase_(count, kNoRecovery),
      recovery_ticks_(count, 0),
      recovery_heading_(count, 0.f),
      arrival_last_(count, 0.0) {
  config_.validate();
  quirks_ = config_.explore.quirks.controllerSide();
}

void DpoBatch::restart(uint32_t l) {
  ForagerBatch::restart(l);
  blocks_.clear(l);
  target_[l] = -1;
  last_collision_[l] = kNever;
  recovery_phase_[l] = kNoRecovery;
  recovery_ticks_[l] = 0;
  recovery_heading_[l] = 0.f;
  arrival_last_[l] = 0.0;
}

void DpoBatch::enterState(uint32_t l, uint8_t next) {
  if (state_[l] == next) return;
  state_[l] = next;
  state_ticks_[l] = 0;
  recovery_phase_[l] = kNoRecovery;
}

void DpoBatch::updateBlocks(uint32_t l, uint32_t i, const SensorData& s, uint32_t b, uint32_t e) {
  // Without line-of-sight data this tick nothing is known to be in sight: only decay.
  const Rect sight =
      s.los_block_offset.size() > i + 1u ? certainSight(los_, s.x[i], s.y[i]) : Rect{0, 0, 0, 0};
  blocks_.update(l, pheromone_, sight, s.los_block_id.data() + b, s.los_block_x.data() + b,
                 s.los_block_y.data() + b, e - b, s.carried_block[i]);
}

bool DpoBatch::selectBlock(uint32_t l, uint32_t i, const SensorData& s) {
  const auto& known = blocks_.of(l);
  const int k = bestByUtility(known, Vec2(s.x[i], s.y[i]), config_.nest_center, config_.exclusion_radius);
  target_[l] = k < 0 ? -1 : known[static_cast<std::size_t>(k)].id;
  return k >= 0;
}

void DpoBatch::transition(uint32_t l, uint32_t i, const SensorData& s) {
  const bool carrying = s.carried_block[i] >= 0;
  const uint8_t ground = s.ground[i], events = s.events[i];
  switch (state(l)) {
    case DpoState::kExplore:
      if (ground == kBlockGround && !carrying && state_ticks_[l] >= config_.explore.min_explore_ticks)
        state_[l] = static_cast<uint8_t>(DpoState::kPickup);  // keeps its exploration time, as CRW
      else if (!carrying && selectBlock(l, i, s))
        enter(l, DpoState::kVector);
      break;
    case DpoState::kVector: {
      const Remembered* t = blocks_.find(l, target_[l]);
      if (t == nullptr) {  // forgotten on the way: pick another one
        if (!selectBlock(l, i, s)) enter(l, DpoState::kExplore);
      } else if (distance(s, i, *t) <= config_.arrival_tolerance) {
        if (ground == kBlockGround) {
          enter(l, DpoState::kPickup);
        } else {  // arrived, but nothing there
          blocks_.forget(l, target_[l]);
          if (!selectBlock(l, i, s)) enter(l, DpoState::kExplore);
        }
      }
      break;
    }
    case DpoState::kPickup:
      if (carrying || (events & kPickupDone)) {
        blocks_.forget(l, s.carried_block[i]);
        blocks_.forget(l, target_[l]);
        target_[l] = -1;
        enter(l, DpoState::kTransport);
      } else if ((events & kBlockVanished) || ground != kBlockGround) {
        blocks_.forget(l, target_[l]);
        target_[l] = -1;
        state_[l] = static_cast<uint8_t>(DpoState::kExplore);  // keeps its exploration time, as CRW
      }
      break;
    default: {  // CRW's delivery; FORDYCA leaves the nest (wander + avoidance) before it acquires a block
      DpoState st = state(l);
      if (deliveryTransition(st, state_ticks_[l], ground, carrying, events,
                             config_.explore.nest_wander_ticks))
        enter(l, st);
      break;
    }
  }
}

bool DpoBatch::secondCollision(uint32_t l, uint64_t tick) const {
  const uint64_t last = last_collision_[l];
  if (last != kNever) return tick - last < config_.collision_window;
  // kFirstCollisionAtZero: FORDYCA's vector_fsm starts with last_collision_time{0} on ARGoS' clock, whose
  // first control step is clock 1 (CSpace::Update increases the clock first): this model's tick 0. So
  // clock 0 is tick -1, and a collision before the first one is a second one while tick + 1 < 300.
  return quirks_.has(Quirk::kFirstCollisionAtZero) && tick + 1 < config_.collision_window;
}

void DpoBatch::vectorTo(uint32_t l, uint32_t i, uint64_t tick, const SensorData& s, const Vec2& goal,
                        CounterRng& rng) {
  // FORDYCA vector_fsm: seek (forced soft turns; obstacles ignored inside the slowing radius), collision
  // avoidance, a new direction after a second collision within collision_window ticks, then recovery.
  const DriveConfig& drive = config_.explore.drive;
  const Vec2 to = goal - Vec2(s.x[i], s.y[i]);
  const double d = to.norm();
  const double theta = heading(l, i, s);  // the exact pose, or FORDYCA's estimate (kHeadingEstimate)
  const bool fordyca_new_direction = quirks_.has(Quirk::kAbsoluteRecoveryAngle);
  const bool threat = s.threatened[i] != 0;
  uint8_t& phase = recovery_phase_[l];
  uint32_t& ticks = recovery_ticks_[l];
  if (threat && ((phase == kNoRecovery && d > config_.slowing_radius) || phase == kStraight)) {
    phase = kAvoid;
    ticks = 0;
  }
  if (phase == kAvoid) {
    if (!threat) {  // the episode is over: its end is what the next collision is measured from
      last_collision_[l] = tick;
      phase = kStraight;
      ticks = 0;
    } else if (secondCollision(l, tick)) {
      const double u = rng.uniform(0.0, config_.recovery_max_offset);
      // kAbsoluteRecoveryAngle: FORDYCA's randomize_vector_angle(X), the x axis rotated by U[0, 1] rad.
      recovery_heading_[l] = static_cast<float>(fordyca_new_direction ? std::atan2(std::sin(u), std::cos(u))
                                                                      : wrapAngle(theta + u));
      phase = kSpin;
      ticks = 0;
    } else {
      const Vec2 avoid = avoidanceForce(s, i, config_.explore.avoidance_force);
      // kTransportWander: vector_fsm's avoidance adds the wander force too when nearly stopped.
      if (nearlyStopped(l, i, s))
        return driveForce(l, avoid + wanderForce(wander_angle_[l], rng, config_.explore), false);
      return driveForce(l, avoid, false);
    }
  }
  if (phase == kSpin) {
    // kAbsoluteRecoveryAngle: FORDYCA's new_direction state drives fsm_drive(.., current_dir - new_dir,
    // hard turn), unwrapped, and a positive angle turns left: it spins away from the new direction.
    // The default model subtracts the pose in float, as it always did (bit-identical runs).
    const double err = fordyca_new_direction ? theta - static_cast<double>(recovery_heading_[l])
                       : quirks_.has(Quirk::kHeadingEstimate) ? wrapAngle(recovery_heading_[l] - theta)
                                                              : wrapAngle(recovery_heading_[l] - s.theta[i]);
    if (std::fabs(err) < config_.recovery_heading_tolerance || ticks >= config_.recovery_spin_ticks) {
      phase = kStraight;
      ticks = 0;
      drive_speed_[l] = 0.0;  // FORDYCA's last fsm_drive was this tick's hard turn (-max, +max)
    } else {
      ++ticks;
      const auto v = static_cast<float>(config_.recovery_spin_speed * drive.max_speed);
      const bool left = fordyca_new_direction ? err > 0 : err >= 0;
      return driveWheels(l, left ? WheelSpeeds{-v, v} : WheelSpeeds{v, -v});
    }
  }
  if (phase == kStraight) {
    if (ticks < config_.recovery_straight_ticks) {
      ++ticks;
      coast(l);  // FORDYCA set_wheel_speeds(0.7 max): not a drive command
      const auto v = static_cast<float>(config_.recovery_straight_speed * drive.max_speed);
      return driveWheels(l, {v, v});
    }
    phase = kNoRecovery;
  }
  if (d < 1e-9) return driveWheels(l, {});
  // Arrival: full force outside the slowing radius, slower inside it but never below slowing_speed_min.
  const double magnitude =
      d > config_.slowing_radius
          ? config_.vector_force
          : std::max(config_.slowing_speed_min, config_.vector_force * d / config_.slowing_radius);
  if (quirks_.has(Quirk::kCompressedArrival))
    return driveForce(l, compressedArrival(l, i, s, to, magnitude), true);
  driveForce(l, toRobotFrame(to / d, theta) * magnitude, /*soft_only=*/true);
}

Vec2 DpoBatch::compressedArrival(uint32_t l, uint32_t i, const SensorData& s, const Vec2& to,
                                 double magnitude) {
  // rcppsw arrival_force::operator(): the angle from the velocity's direction to the target, wrapped, then
  // unwrapped against the last one; the force is vector2d(length, angle_diff), Cartesian (two doubles).
  double vx, vy;
  linearVelocity(l, i, s, vx, vy);
  double diff = std::atan2(to.y(), to.x()) - std::atan2(vy, vx);
  diff = std::atan2(std::sin(diff), std::cos(diff));
  if (std::fabs(diff - arrival_last_[l]) > kPi) diff -= std::copysign(2 * kPi, diff);
  arrival_last_[l] = diff;
  return {magnitude, diff};
}

void DpoBatch::act(uint32_t l, uint32_t i, uint64_t tick, const SensorData& s, DpoState st, const Vec2* goal,
                   CounterRng& rng, uint8_t& request) {
  request = kNone;
  switch (st) {
    case DpoState::kPickup:
      request = kPickup;  // stopped on the block
      return driveWheels(l, {});
    case DpoState::kDrop:
      request = kDrop;
      return driveWheels(l, {});
    case DpoState::kVector:
      if (goal != nullptr) return vectorTo(l, i, tick, s, *goal, rng);
      break;
    case DpoState::kTransport:
      if (goal != nullptr) return vectorTo(l, i, tick, s, *goal, rng);
      return driveMotion(l, Motion::kTransport, s, rng, nearlyStopped(l, i, s));
    case DpoState::kNestWander:
      return driveMotion(l, Motion::kNestWander, s, rng);
    case DpoState::kLeaveNest:
      return driveMotion(l, Motion::kLeaveNest, s, rng);
    default:
      break;
  }
  driveMotion(l, Motion::kExplore, s, rng);
}

void DpoBatch::step(uint64_t tick, const SensorData& s, CommandData& out, ControllerStatus& status) {
  prepare(out, status, dpoStateNames());
  beginDrives();
  driveAll(tick, s, config_.explore, out, status);  // chooseDrives() per strip, then the strip's drives
}

void DpoBatch::chooseDrives(uint32_t first, uint32_t end, uint64_t tick, const SensorData& s,
                            CommandData& out) {
  for (uint32_t l = first; l < end; ++l) {
    if (idle(l, s, out)) {
      request_[l] = kStill;
      continue;
    }
    const uint32_t i = first_id_ + l;
    blocks_.prefetch(l + kAhead);
    observeBlocks(l, i, s);
    transition(l, i, s);
    const DpoState st = state(l);
    const Remembered* t = st == DpoState::kVector ? blocks_.find(l, target_[l]) : nullptr;
    const Vec2 goal = t != nullptr ? Vec2(t->x, t->y) : Vec2(0, 0);
    CounterRng rng = rngAt(l, tick);
    request_[l] = kNone;
    act(l, i, tick, s, st, t != nullptr ? &goal : nullptr, rng, request_[l]);
  }
}

}  // namespace swarm_forage
