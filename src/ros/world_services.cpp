// world_node's services (world/reset, world/info) and its live knob (real_time_factor, dynamic_reconfigure).
#include <algorithm>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/ros/params.hpp"
#include "swarm_forage/ros/run_messages.hpp"
#include "swarm_forage/ros/world_messages.hpp"
#include "swarm_forage/ros/world_ros.hpp"

namespace swarm_forage {

WorldPaceConfig WorldRos::repace(const WorldPaceConfig& requested) {
  WorldPaceConfig now = requested;
  if (requested.real_time_factor == real_time_factor_) return now;
  if (lockstep_)
    throw ParameterError("~real_time_factor paces realtime runs only; this world runs ~mode lockstep");
  real_time_factor_ =
      valueInRange("real_time_factor", requested.real_time_factor, kMinRealTimeFactor, kMaxRealTimeFactor);
  ROS_INFO("world: real_time_factor %g", now.real_time_factor);
  return now;
}

PopulationRatesConfig WorldRos::rerate(const PopulationRatesConfig& requested) {
  PopulationConfig next;  // the rates only (max_size stays the run's)
  next.death = requested.death;
  next.birth = requested.birth;
  next.malfunction = requested.malfunction;
  next.repair = requested.repair;
  std::lock_guard<std::mutex> lock(rates_mutex_);
  if (next.death == rates_now_.death && next.birth == rates_now_.birth &&
      next.malfunction == rates_now_.malfunction && next.repair == rates_now_.repair)
    return requested;  // start-up, or nothing changes
  if (lockstep_)
    throw ParameterError(
        "~population rates change live in realtime runs only; this world runs ~mode lockstep");
  next.validate(1);  // the start-up rule: names the parameter and its range
  pending_rates_ = rates_now_ = next;
  return requested;
}

bool WorldRos::onReset(Reset::Request& req, Reset::Response& res) {
  try {
    const RunDescription& now = run_->description();
    const bool external =
        !now.external.empty() && (req.controller.empty() ? now.controller : req.controller) == now.external;
    // Throws for an unknown kind (loading a plugin's); "swarm_forage/crw" is crw.
    if (!external && !req.controller.empty()) req.controller = controllerKind(req.controller).name;
    const std::string& kind = req.controller.empty() ? now.controller : req.controller;
    if (req.seed > static_cast<uint32_t>(kMaxSeed))
      throw ParameterError("seed must be in [0, " + std::to_string(kMaxSeed) + "] as ~seed (got " +
                           std::to_string(req.seed) + ")");
    // Validated as the run will configure it (an external controller needs no line of sight, no cache).
    WorldConfig next = external ? now.world : configuredFor(now.world, kind);
    if (req.seed != 0) next.seed = req.seed;
    if (req.swarm_size != 0) next.n_robots = req.swarm_size;
    next.validate();
    pending_reset_ = PendingReset{next.seed, next.n_robots, req.controller};
    res.success = true;
    res.run = run_no_ + 1;
    res.message = "run " + std::to_string(res.run) + " starts with seed " + std::to_string(next.seed) +
                  " and " + std::to_string(next.n_robots) + " robots";
  } catch (const ParameterError& e) {
    res.success = false;
    res.run = run_no_;
    res.message = e.what();
  }
  return true;
}

bool WorldRos::onInfo(Info::Request&, Info::Response& res) {
  const World& world = run_->world();
  res.run = runInfoMsg(run_->description(), ns_per_tick_);
  res.nest = nestMsg(world.config().arena);
  const Rect s = world.config().arena.source();
  res.source_x = {static_cast<float>(s.min_x), static_cast<float>(s.max_x)};
  res.source_y = {static_cast<float>(s.min_y), static_cast<float>(s.max_y)};
  res.caches = cacheMsg(world.cache());
  return true;
}

}  // namespace swarm_forage
