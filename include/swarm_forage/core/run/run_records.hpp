#pragma once
// What a run records, as core structs (docs/design.md, One run engine): the run engine hands them to its
// sinks, and the ROS sinks turn them into messages (src/ros/messages/run_messages.cpp) field for field.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/metrics/run_library.hpp"
#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

/// The condition V applied at one tick and the waveform that gave it (environment/throttle).
struct ConditionSample {
  uint64_t tick = 0;
  double value = 0;
  Condition condition;
  uint32_t seq = 0;  // of the message it came in (a topic's sequence number): a bag holds what was received
};
/// What an environment applies at `tick` of a run at `ticks_per_second` (exact at the step time alpha).
ConditionSample conditionAt(const Condition& condition, uint64_t tick, double ticks_per_second);
/// Whether a record must hold `c`: at tick 0 and whenever V or the waveform changes (a live change; V of
/// every tick is in the performance records anyway). `last` is the sample last recorded.
bool conditionChanged(const ConditionSample& c, std::optional<ConditionSample>& last);

/// What a run is. All but the controller constants and the condition are known before tick 0; those two
/// are told by the tick-0 replies, which fix the run's identity (world/run_info).
struct RunDescription {
  uint32_t run = 0;        // counts world/reset
  std::string controller;  // the kind the world announces (world/sensors): what controller_node builds
  std::string external;    // a controller served by nodes outside this build (~external_controller), or ""
  WorldConfig world;       // with the features the controller needs (configuredFor; none for an external one)
  uint64_t ticks = 0;
  std::string mode = "lockstep";
  std::string controller_constants;          // canonical "kind/name=value" words; "" until tick 0
  std::optional<ConditionSample> condition;  // tick 0's; none: no environment (V = 0 throughout)
  bool fixed = false;                        // tick 0 has told the constants and the condition

  /// The run's controller as recorded: `controller`, or "controller+external" when an external controller
  /// serves ranges next to a kind of this build (docs/rospy-controller.md).
  std::string name() const;
  /// The run library's key (with `interval` as the metrics' sample interval).
  RunKey key(uint32_t interval = 0) const;
  /// RunKey::identity() once fixed, else "": a run stopped before tick 0 has no identity.
  std::string identity() const;
};

/// A run's bag: `bag` (an explicit path; a later run of the same world appends "_runR") or a file named
/// by runBagName() in `bag_dir`; "" when neither is set.
std::string runBagPath(const std::string& bag, const std::string& bag_dir, const RunDescription& run);
/// The file name of a run's bag:
/// controller_arena_nN_condition[_noise][_population][_model]_seedS_IDENTITY.bag (the tags of SaaNoise,
/// PopulationConfig and FordycaQuirks) once the identity is fixed; controller_arena_nN_seedS_runR.bag until
/// then (the name of a record that never reaches tick 0).
std::string runBagName(const RunDescription& run);
/// `s` with every character a file name should not hold replaced by '_'.
std::string fileSafe(std::string s);

/// What one controller range did in one tick (swarm/status).
struct StatusRecord {
  uint64_t tick = 0;
  uint32_t run = 0, first_id = 0, count = 0, swarm_size = 0;
  std::string controller;
  ControllerStatus status;
  std::string constants;  // in a range's first record of a run only
  std::string source;     // who sent it (a controller node); not recorded
  uint32_t seq = 0;  // of the message it came in (a topic's sequence number): a bag holds what was received
};
StatusRecord statusRecord(const ControllerStatus& status, const CommandData& commands, uint64_t tick,
                          uint32_t run, uint32_t swarm_size, const std::string& controller,
                          const std::string& constants);

/// The swarm's foraging in one tick (world/performance).
struct PerformanceRecord {
  uint64_t tick = 0;
  uint32_t run = 0, swarm_size = 0, delivered = 0, carrying = 0;
  uint64_t cumulative = 0;
  double throttle = 0;  // V applied this tick
  bool last = false;    // the run's final tick
};

/// The population after one tick's step and that tick's events (world/population), every tick of a run
/// with population dynamics (docs/robustness-population.md).
struct PopulationRecord {
  uint64_t tick = 0;
  uint32_t run = 0;
  uint32_t active = 0, present = 0, queue = 0, max_size = 0;    // present: active + awaiting repair
  std::vector<uint32_t> deaths, births, malfunctions, repairs;  // robot ids
  double death = 0, birth = 0, malfunction = 0, repair = 0;     // the rates in force
  bool changed = false;  // changed by hand (World::setPopulationRates) at or before this tick
};
PopulationRecord populationRecord(const PopulationDynamics& population, uint64_t tick, uint32_t run,
                                  uint32_t n_robots);

/// How a run ended (world/run_end), however it stopped.
struct RunEndRecord {
  uint32_t run = 0;
  uint64_t ticks_done = 0, ticks = 0;
  bool complete = false;  // every tick was stepped and the record holds its name
  std::string reason;     // why not ("" when complete)
  std::string identity;   // RunDescription::identity()
  std::string bag;        // where the run is recorded ("" when not)
};
/// Appends how a run ended to a YAML list file (~outcome, outcome:=): one "- {run: ..., complete: ...}"
/// line per run; false when it cannot be written.
bool appendOutcome(const std::string& path, const RunEndRecord& end);

}  // namespace swarm_forage
