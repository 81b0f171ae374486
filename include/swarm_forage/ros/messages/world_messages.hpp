#pragma once
// Building world_node's messages from the core world.
#include <geometry_msgs/TransformStamped.h>
#include <swarm_forage/BlockArray.h>
#include <swarm_forage/CacheArray.h>
#include <swarm_forage/Nest.h>
#include <swarm_forage/RobotStateArray.h>
#include <swarm_forage/SensorBatch.h>

#include <optional>
#include <string>
#include <utility>

#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

Nest nestMsg(const ArenaConfig& arena);
CacheArray cacheMsg(const StaticCache& cache);
/// world/caches at `tick`.
CacheArray cachesMsg(const StaticCache& cache, uint64_t tick, const ros::Time& stamp);
/// world/sensors of `tick`: every robot's readings, and what a controller needs to start a run.
SensorBatch::Ptr sensorsMsg(const World& world, const SensorData& sensors, uint64_t tick, uint32_t run,
                            const std::string& controller, const ros::Time& stamp);
geometry_msgs::TransformStamped staticFrame(const std::string& child, double x, double y);
RobotStateArray robotsMsg(const SensorData& sensors, uint64_t tick, const ros::Time& stamp);
/// Carried blocks are placed at their carrier (from `sensors`).
BlockArray blocksMsg(const BlockField& field, const SensorData& sensors, uint64_t tick,
                     const ros::Time& stamp);

}  // namespace swarm_forage
