// Small controller plugins for swarm_forage's tests (docs/controller-plugins.md): a deterministic one
// that forages (CRW at a scaled top speed), one whose batch throws when it is made and one whose batch
// throws at a given tick, one that sends a command the world cannot step at a given tick, and one that
// cannot even be created. Written only against swarm_forage's public headers.
#include <limits>
#include <pluginlib/class_list_macros.hpp>
#include <stdexcept>
#include <string>

#include "swarm_forage/controller_plugin.hpp"
#include "swarm_forage/core/controllers/crw.hpp"

namespace swarm_forage_examples {

using swarm_forage::ConstantVisitor;
using swarm_forage::ControllerConfigs;
using swarm_forage::ControllerKind;
using swarm_forage::CrwBatch;
using swarm_forage::CrwConfig;

// ---- slow_crw: CRW whose top speed is scaled (it reads crw's constants too: builds_on) ----
struct SlowCrwConfig {
  double speed_scale = 0.5;  // of crw/max_speed, in (0, 1]
  void validate() const {
    if (!(speed_scale > 0.0 && speed_scale <= 1.0))
      throw swarm_forage::ParameterError("swarm_forage_examples/slow_crw/speed_scale must be in (0, 1]");
  }
};
void visitSlowCrw(SlowCrwConfig& c, ConstantVisitor& v) { v.number("speed_scale", c.speed_scale); }

class SlowCrw : public swarm_forage::ControllerPlugin {
 public:
  ControllerKind kind() const override {
    ControllerKind k;
    k.name = "swarm_forage_examples/slow_crw";
    k.display_name = "slow CRW";
    k.colour = "tab:brown";
    k.builds_on = "crw";
    k.constants = swarm_forage::sectionOf(visitSlowCrw);
    k.defaults = "config/slow_crw.yaml";
    k.make = [](const ControllerConfigs& c, uint32_t seed, uint32_t first_id, uint32_t count) {
      CrwConfig crw = c.of<CrwConfig>("crw");
      const double scale = c.of<SlowCrwConfig>("swarm_forage_examples/slow_crw").speed_scale;
      crw.drive.max_speed *= scale;
      crw.drive.hard_turn_speed *= scale;  // CRW requires it at most max_speed
      return std::make_unique<CrwBatch>(crw, seed, first_id, count);
    };
    return k;
  }
};

// ---- fails_to_start: its batch throws when it is made ----
struct NoConstants {
  void validate() const {}
};
void visitNothing(NoConstants&, ConstantVisitor&) {}

class FailsToStart : public swarm_forage::ControllerPlugin {
 public:
  ControllerKind kind() const override {
    ControllerKind k;
    k.name = "swarm_forage_examples/fails_to_start";
    k.display_name = "fails to start (test)";
    k.colour = "tab:gray";
    k.constants = swarm_forage::sectionOf(visitNothing);
    k.defaults = "config/fails_to_start.yaml";
    k.make = [](const ControllerConfigs&, uint32_t, uint32_t, uint32_t) -> std::unique_ptr<CrwBatch> {
      throw std::runtime_error("this batch refuses to be made (a test fixture)");
    };
    return k;
  }
};

// ---- fails_at_tick: CRW until its batch throws at ~swarm_forage_examples/fails_at_tick/tick ----
struct FailsAtTickConfig {
  uint32_t tick = 5;
  void validate() const {}
};
void visitFailsAtTick(FailsAtTickConfig& c, ConstantVisitor& v) { v.count("tick", c.tick); }

class FailingBatch : public swarm_forage::ControllerBatch {
 public:
  FailingBatch(std::unique_ptr<CrwBatch> crw, uint64_t at) : crw_(std::move(crw)), at_(at) {}
  std::string name() const override { return "swarm_forage_examples/fails_at_tick"; }
  void step(uint64_t tick, const swarm_forage::SensorData& s, swarm_forage::CommandData& out,
            swarm_forage::ControllerStatus& status) override {
    if (tick == at_) throw std::runtime_error("failing on purpose (a test fixture)");
    crw_->step(tick, s, out, status);
  }

 private:
  std::unique_ptr<CrwBatch> crw_;
  uint64_t at_;
};

class FailsAtTick : public swarm_forage::ControllerPlugin {
 public:
  ControllerKind kind() const override {
    ControllerKind k;
    k.name = "swarm_forage_examples/fails_at_tick";
    k.display_name = "fails at a tick (test)";
    k.colour = "tab:gray";
    k.builds_on = "crw";
    k.constants = swarm_forage::sectionOf(visitFailsAtTick);
    k.defaults = "config/fails_at_tick.yaml";
    k.make = [](const ControllerConfigs& c, uint32_t seed, uint32_t first_id, uint32_t count) {
      return std::make_unique<FailingBatch>(
          std::make_unique<CrwBatch>(c.of<CrwConfig>("crw"), seed, first_id, count),
          c.of<FailsAtTickConfig>("swarm_forage_examples/fails_at_tick").tick);
    };
    return k;
  }
};

// ---- sends_bad_commands: CRW, but at ~.../tick robot ~.../robot gets a NaN left wheel speed, or the
// request code ~.../request when it is not 0 ----
struct BadCommandsConfig {
  uint32_t tick = 5, robot = 0, request = 0;
  void validate() const {
    if (request > 255)
      throw swarm_forage::ParameterError(
          "swarm_forage_examples/sends_bad_commands/request must be in [0, 255]");
  }
};
void visitBadCommands(BadCommandsConfig& c, ConstantVisitor& v) {
  v.count("tick", c.tick);
  v.count("robot", c.robot);
  v.count("request", c.request);
}

class BadCommandsBatch : public swarm_forage::ControllerBatch {
 public:
  BadCommandsBatch(std::unique_ptr<CrwBatch> crw, const BadCommandsConfig& c) : crw_(std::move(crw)), c_(c) {}
  std::string name() const override { return "swarm_forage_examples/sends_bad_commands"; }
  void step(uint64_t tick, const swarm_forage::SensorData& s, swarm_forage::CommandData& out,
            swarm_forage::ControllerStatus& status) override {
    crw_->step(tick, s, out, status);
    if (tick != c_.tick || c_.robot < out.first_id || c_.robot - out.first_id >= out.size()) return;
    const std::size_t i = c_.robot - out.first_id;
    if (c_.request == 0)
      out.left[i] = std::numeric_limits<float>::quiet_NaN();
    else
      out.request[i] = static_cast<uint8_t>(c_.request);
  }

 private:
  std::unique_ptr<CrwBatch> crw_;
  BadCommandsConfig c_;
};

class SendsBadCommands : public swarm_forage::ControllerPlugin {
 public:
  ControllerKind kind() const override {
    ControllerKind k;
    k.name = "swarm_forage_examples/sends_bad_commands";
    k.display_name = "sends bad commands (test)";
    k.colour = "tab:gray";
    k.builds_on = "crw";
    k.constants = swarm_forage::sectionOf(visitBadCommands);
    k.defaults = "config/sends_bad_commands.yaml";
    k.make = [](const ControllerConfigs& c, uint32_t seed, uint32_t first_id, uint32_t count) {
      return std::make_unique<BadCommandsBatch>(
          std::make_unique<CrwBatch>(c.of<CrwConfig>("crw"), seed, first_id, count),
          c.of<BadCommandsConfig>("swarm_forage_examples/sends_bad_commands"));
    };
    return k;
  }
};

// ---- fails_to_load: the plugin itself throws when pluginlib creates it ----
class FailsToLoad : public swarm_forage::ControllerPlugin {
 public:
  FailsToLoad() { throw std::runtime_error("this plugin refuses to be created (a test fixture)"); }
  ControllerKind kind() const override { return {}; }
};

}  // namespace swarm_forage_examples

PLUGINLIB_EXPORT_CLASS(swarm_forage_examples::FailsToLoad, swarm_forage::ControllerPlugin)
PLUGINLIB_EXPORT_CLASS(swarm_forage_examples::SlowCrw, swarm_forage::ControllerPlugin)
PLUGINLIB_EXPORT_CLASS(swarm_forage_examples::FailsToStart, swarm_forage::ControllerPlugin)
PLUGINLIB_EXPORT_CLASS(swarm_forage_examples::FailsAtTick, swarm_forage::ControllerPlugin)
PLUGINLIB_EXPORT_CLASS(swarm_forage_examples::SendsBadCommands, swarm_forage::ControllerPlugin)
