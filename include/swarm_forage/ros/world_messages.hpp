#pragma once
// Building world_node's messages from the core world.
#include <geometry_msgs/TransformStamped.h>
#include <swarm_forage/BlockArray.h>
#include <swarm_forage/CacheArray.h>
#include <swarm_forage/Nest.h>
#include <swarm_forage/RobotStateArray.h>

#include <optional>
#include <string>
#include <utility>

#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

Nest nestMsg(const ArenaConfig& arena);
CacheArray cacheMsg(const StaticCache& cache);
/// world/caches for `tick` when the cache appeared, vanished or changed its block count since `last`
/// (always at tick 0); `last` is updated.
std::optional<CacheArray> cacheChange(const StaticCache& cache, uint64_t tick, const ros::Time& stamp,
                                      std::pair<bool, std::size_t>& last);
geometry_msgs::TransformStamped staticFrame(const std::string& child, double x, double y);
RobotStateArray robotsMsg(const SensorData& sensors, uint64_t tick, const ros::Time& stamp);
/// Carried blocks are placed at their carrier (from `sensors`).
BlockArray blocksMsg(const BlockField& field, const SensorData& sensors, uint64_t tick,
                     const ros::Time& stamp);

}  // namespace swarm_forage
