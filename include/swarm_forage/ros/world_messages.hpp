#pragma once
// Building world_node's messages from the core world.
#include <geometry_msgs/TransformStamped.h>
#include <swarm_forage/BlockArray.h>
#include <swarm_forage/CacheArray.h>
#include <swarm_forage/Nest.h>
#include <swarm_forage/RobotStateArray.h>

#include <string>

#include "swarm_forage/core/world.hpp"

namespace swarm_forage {

Nest nestMsg(const ArenaConfig& arena);
CacheArray cacheMsg(const StaticCache& cache);
geometry_msgs::TransformStamped staticFrame(const std::string& child, double x, double y);
RobotStateArray robotsMsg(const SensorData& sensors, uint64_t tick, const ros::Time& stamp);
/// Carried blocks are placed at their carrier (from `sensors`).
BlockArray blocksMsg(const BlockField& field, const SensorData& sensors, uint64_t tick,
                     const ros::Time& stamp);

}  // namespace swarm_forage
