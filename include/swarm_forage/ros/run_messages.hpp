#pragma once
// The messages a run is recorded as, built in one place for the node graph (world, controller and
// environment nodes) and for run_experiment, so that both write the same bag.
#include <swarm_forage/Performance.h>
#include <swarm_forage/RunEnd.h>
#include <swarm_forage/RunInfo.h>
#include <swarm_forage/SwarmStatus.h>
#include <swarm_forage/Throttle.h>

#include <optional>
#include <string>

#include "swarm_forage/core/controller.hpp"
#include "swarm_forage/core/waveform.hpp"
#include "swarm_forage/core/world.hpp"

namespace swarm_forage {

/// What environment_node publishes for `tick` (stamped at the tick's simulated time).
Throttle throttleMsg(const WaveformConfig& waveform, uint64_t tick, double ticks_per_second,
                     uint64_t ns_per_tick);

/// Whether two throttles come from the same waveform (name and parameters; V may differ).
bool sameWaveform(const Throttle& a, const Throttle& b);
/// Why a run whose waveform became `t` mid-run is kept out of a run library.
std::string reconfiguredLive(const Throttle& t);

/// Whether a run's bag records environment/throttle `t`: at tick 0 and whenever V or the waveform changes
/// (a live reconfiguration; the value applied each tick is in world/performance too, so an unchanging
/// condition costs nothing per tick). `last` is the throttle last recorded.
bool recordThrottle(const Throttle& t, std::optional<Throttle>& last);

/// What a controller node answers for a tick: `constants` only in its first answer of a run.
SwarmStatus statusMsg(const ControllerStatus& status, const CommandData& commands, uint64_t tick,
                      uint32_t run, uint32_t swarm_size, const std::string& controller,
                      const ros::Time& stamp, const std::string& constants);

/// world/performance after a tick's step.
Performance performanceMsg(const World& world, const StepResult& result, uint64_t tick, uint32_t run,
                           double throttle, bool last, const ros::Time& stamp);

/// world/run_info: the run's identity (constants as reported by the controllers, "" before tick 0;
/// `throttle` the environment's tick-0 answer, none for an ideal run without an environment).
RunInfo runInfoMsg(const WorldConfig& config, const std::string& controller, uint32_t run, uint64_t ticks,
                   const std::string& mode, const std::string& controller_constants,
                   const std::optional<Throttle>& throttle, uint64_t ns_per_tick);

/// world/run_end: `reason` "" for a run that reached its last tick (`ticks_done` = `ticks`).
RunEnd runEndMsg(uint32_t run, uint64_t ticks_done, uint64_t ticks, const std::string& reason,
                 const std::string& identity, uint64_t ns_per_tick);
/// Appends how a run ended to a YAML list file (~outcome: one "- {run: ..., complete: ...}" line per
/// run); false when it cannot be written.
bool appendOutcome(const std::string& path, const RunEnd& end);

/// `s` with every character a file name should not hold replaced by '_'.
std::string fileSafe(std::string s);
/// The file name (no folder) of a run's bag: controller_arena_nN_condition_seedS_IDENTITY.bag.
std::string runBagName(const RunInfo& info);

}  // namespace swarm_forage
