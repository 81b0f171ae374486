// world_node's services (world/reset, world/info) and its live knobs (real_time_factor and the noise,
// dynamic_reconfigure).
#include <algorithm>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/ros/messages/run_messages.hpp"
#include "swarm_forage/ros/messages/world_messages.hpp"
#include "swarm_forage/ros/params/params.hpp"
#include "swarm_forage/ros/world_node/world_ros.hpp"

namespace swarm_forage {

WorldPaceConfig WorldRos::repace(const WorldPaceConfig& requested) {
  WorldPaceConfig now = requested;
  if (requested.real_time_factor == real_time_factor_) return now;
  if (lockstep_)
    throw ParameterError("~real_time_factor paces realtime runs only; this world runs ~mode lockstep");
  const ParamSpec& rtf = paramSpec("real_time_factor");  // the start-up range
  real_time_factor_ = valueInRange("real_time_factor", requested.real_time_factor, rtf.lo, rtf.hi);
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

namespace {
// The fields of cfg/Noise.cfg, in SaaNoise::deviceNames() order.
using ModelField = std::string NoiseConfig::*;
using LevelField = double NoiseConfig::*;
const std::pair<ModelField, LevelField> kNoiseFields[] = {
    {&NoiseConfig::proximity_model, &NoiseConfig::proximity_level},
    {&NoiseConfig::light_model, &NoiseConfig::light_level},
    {&NoiseConfig::position_model, &NoiseConfig::position_level},
    {&NoiseConfig::heading_model, &NoiseConfig::heading_level},
    {&NoiseConfig::wheels_model, &NoiseConfig::wheels_level}};
}  // namespace

NoiseConfig noiseConfig(const SaaNoise& noise) {
  NoiseConfig c;
  for (std::size_t k = 0; k < std::size(kNoiseFields); ++k) {
    const DeviceNoise& d = noise.device(static_cast<NoisyDevice>(k));
    c.*kNoiseFields[k].first = d.model == NoiseModel::kUniform ? "uniform" : "gaussian";
    c.*kNoiseFields[k].second = d.level;
  }
  c.ground_level = noise.ground;
  return c;
}

SaaNoise noiseOf(const NoiseConfig& c) {
  SaaNoise noise;
  for (std::size_t k = 0; k < std::size(kNoiseFields); ++k) {
    DeviceNoise& d = noise.device(static_cast<NoisyDevice>(k));
    const std::string& model = c.*kNoiseFields[k].first;
    if (model != "gaussian" && model != "uniform")
      throw ParameterError("~noise/" + SaaNoise::deviceNames()[k] + "_model '" + model +
                           "' is not valid; valid: gaussian, uniform");
    d.model = model == "uniform" ? NoiseModel::kUniform : NoiseModel::kGaussian;
    d.level = c.*kNoiseFields[k].second;
  }
  noise.ground = c.ground_level;
  noise.validate();
  return noise;
}

NoiseConfig WorldRos::renoise(const NoiseConfig& requested) {
  const SaaNoise next = noiseOf(requested);  // throws: nothing changes
  const std::lock_guard<std::mutex> lock(noise_mutex_);
  if (next.describe() == live_noise_.describe()) return noiseConfig(next);
  if (lockstep_)
    throw ParameterError(
        "~noise changes live in realtime runs only; this world runs ~mode lockstep (a "
        "lockstep run's noise is a start-up parameter, in its identity)");
  live_noise_ = next;
  noise_pending_ = true;
  ROS_INFO("world: noise from the next tick on: %s", next.enabled() ? next.describe().c_str() : "none");
  return noiseConfig(next);
}

void WorldRos::applyNoiseChange() {
  SaaNoise next;
  {
    const std::lock_guard<std::mutex> lock(noise_mutex_);
    if (!noise_pending_) return;
    noise_pending_ = false;
    next = live_noise_;
  }
  run_->changeNoise(next);  // validated by renoise; the sinks record and publish world/noise
}

void WorldRos::noiseChanged(uint64_t tick, const SaaNoise& noise) {
  noise_pub_.publish(noiseChangeMsg(run_no_, tick, noise, ns_per_tick_));
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
