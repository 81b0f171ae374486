#include "swarm_forage_examples/levy.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "swarm_forage/controller_plugin.hpp"
#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/config.hpp"  // ParameterError

namespace swarm_forage_examples {

using namespace swarm_forage;

namespace {
const std::vector<std::string>& stateNames() {
  static const std::vector<std::string> names = {"explore",     "pickup", "transport",
                                                 "nest_wander", "drop",   "leave_nest"};
  return names;
}

void require(bool ok, const std::string& what) {
  if (!ok) throw ParameterError(std::string(kLevyKind) + "/" + what);
}
}  // namespace

void LevyConfig::validate() const {
  require(mu > 1 && mu <= 3, "mu must be in (1, 3]");
  require(l_min > 0 && l_min <= 100, "l_min must be in (0, 100] m");
  require(l_max > l_min && l_max <= 1000, "l_max must be in (l_min, 1000] m");
  require(step_force > 0 && step_force <= 100, "step_force must be in (0, 100] cm/s");
  require(avoidance_force >= 0 && avoidance_force <= 100, "avoidance_force must be in [0, 100] cm/s");
}

void visitLevyParameters(LevyConfig& c, ConstantVisitor& v) {
  v.number("mu", c.mu);
  v.number("l_min", c.l_min);
  v.number("l_max", c.l_max);
  v.number("step_force", c.step_force);
  v.number("avoidance_force", c.avoidance_force);
}

double levyStepLength(double u, double mu, double l_min, double l_max) {
  // F(l) = (l^(1-mu) - l_min^(1-mu)) / (l_max^(1-mu) - l_min^(1-mu)), solved for l; 1 - mu < 0.
  const double e = 1.0 - mu, a = std::pow(l_min, e), b = std::pow(l_max, e);
  return std::pow(a + u * (b - a), 1.0 / e);
}

LevyBatch::LevyBatch(const LevyConfig& levy, const CrwConfig& crw, uint32_t seed, uint32_t first_id,
                     uint32_t count)
    : ForagerBatch(seed, first_id, count),
      levy_(levy),
      crw_(crw),
      heading_(count, 0.0),
      step_length_(count, 0.0),
      remaining_(count, 0.0),
      last_x_(count, 0.f),
      last_y_(count, 0.f),
      steps_started_(count, 0) {
  levy_.validate();
  crw_.validate();
}

WheelSpeeds LevyBatch::explore(uint32_t l, uint64_t tick, const SensorData& s) {
  const uint32_t i = first_id_ + l;
  remaining_[l] -= std::hypot(s.x[i] - last_x_[l], s.y[i] - last_y_[l]);
  if (s.threatened[i]) {
    // An obstacle ends the step. Dodge as CRW explores (straight ahead plus avoidance, robot frame):
    // pulling towards the old heading would hold the robot at the wall it met.
    remaining_[l] = 0;
    const Vec2 avoid = avoidanceForce(s, i, levy_.avoidance_force);
    return steer(Vec2(levy_.step_force, 0) + avoid, crw_.drive, /*soft_only=*/false);
  }
  if (remaining_[l] <= 0) {
    // The robot's only draws this tick: a pure function of (seed, robot, tick), whatever the split.
    CounterRng rng(seed_, RngStream::kController, i, tick);
    step_length_[l] = remaining_[l] = levyStepLength(rng.uniform(), levy_.mu, levy_.l_min, levy_.l_max);
    heading_[l] = rng.uniform(-kPi, kPi);
    ++steps_started_[l];
  }
  // Towards the step's heading, turning in place first when far off it.
  const double error = wrapAngle(heading_[l] - s.theta[i]);
  return steer(Vec2(std::cos(error), std::sin(error)) * levy_.step_force, crw_.drive, /*soft_only=*/false);
}

void LevyBatch::restart(uint32_t l) {
  ForagerBatch::restart(l);
  heading_[l] = step_length_[l] = remaining_[l] = 0.0;  // a fresh step at its next exploring tick
  last_x_[l] = last_y_[l] = 0.f;
}

void LevyBatch::step(uint64_t tick, const SensorData& s, CommandData& out, ControllerStatus& status) {
  prepare(out, status, stateNames());
  for (uint32_t l = 0; l < count(); ++l) {
    // Population dynamics: a robot out of the swarm stands still and keeps its state; a newcomer starts
    // afresh (restart). Without population dynamics every robot is in the swarm.
    if (idle(l, s, out)) continue;
    const uint32_t i = first_id_ + l;
    const bool carrying = s.carried_block[i] >= 0;
    auto state = static_cast<LevyState>(state_[l]);
    if (state == LevyState::kExplore) {
      if (s.ground[i] == kBlockGround && !carrying && state_ticks_[l] >= crw_.min_explore_ticks)
        state = LevyState::kPickup;  // keeps its exploration time, should the block vanish
    } else if (state == LevyState::kPickup) {
      if (carrying || (s.events[i] & kPickupDone)) {
        state = LevyState::kTransport;
        state_ticks_[l] = 0;
      } else if (s.ground[i] != kBlockGround) {
        state = LevyState::kExplore;
      }
    } else if (deliveryTransition(state, state_ticks_[l], s.ground[i], carrying, s.events[i],
                                  crw_.nest_wander_ticks)) {
      state_ticks_[l] = 0;
      if (state == LevyState::kExplore) remaining_[l] = 0;  // out of the nest: a fresh step
    }
    state_[l] = static_cast<uint8_t>(state);

    WheelSpeeds w;
    uint8_t request = kNone;
    if (state == LevyState::kExplore) {
      w = explore(l, tick, s);
    } else if (state == LevyState::kPickup) {
      request = kPickup;
    } else if (state == LevyState::kDrop) {
      request = kDrop;
    } else {
      // Carrying home, wandering in the nest and leaving it: CRW's motions (forage_common.hpp).
      const Motion m = state == LevyState::kTransport    ? Motion::kTransport
                       : state == LevyState::kNestWander ? Motion::kNestWander
                                                         : Motion::kLeaveNest;
      CounterRng rng(seed_, RngStream::kController, i, tick);
      w = motionWheels(m, s, i, wander_angle_[l], rng, crw_);
    }
    last_x_[l] = s.x[i];
    last_y_[l] = s.y[i];
    finish(l, tick, s, w, request, out, status);
  }
}

}  // namespace swarm_forage_examples

// The plugin: the kind, declared as a built-in registers its own (controller_registry.hpp), found by its
// name through pluginlib (controller_plugins.xml).
namespace swarm_forage_examples {

class LevyPlugin : public ControllerPlugin {
 public:
  ControllerKind kind() const override {
    ControllerKind k;
    k.name = kLevyKind;
    k.display_name = "Levy";
    k.colour = "tab:red";
    k.builds_on = "crw";  // carries, wanders in the nest and leaves it as CRW does, with CRW's constants
    k.constants = sectionOf(visitLevyParameters);
    k.defaults = "config/levy.yaml";
    k.make = [](const ControllerConfigs& c, uint32_t seed, uint32_t first_id, uint32_t count) {
      return std::make_unique<LevyBatch>(c.of<LevyConfig>(kLevyKind), c.of<CrwConfig>("crw"), seed, first_id,
                                         count);
    };
    return k;
  }
};

}  // namespace swarm_forage_examples

SWARM_FORAGE_EXPORT_CONTROLLER(swarm_forage_examples::LevyPlugin)
