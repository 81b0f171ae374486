#pragma once
// A run's messages as the core's RunFollower takes them: live (metrics_node) or recorded (readRunBag,
// read_run), so that both count a run the same way. Each message becomes the run engine's record of it
// through run_messages' conversions.
#include <rosbag/message_instance.h>
#include <swarm_forage/Performance.h>
#include <swarm_forage/RunEnd.h>
#include <swarm_forage/RunInfo.h>
#include <swarm_forage/SwarmStatus.h>
#include <swarm_forage/Throttle.h>

#include <string>

#include "swarm_forage/core/metrics/run_follower.hpp"
#include "swarm_forage/ros/messages/condition_ros.hpp"
#include "swarm_forage/ros/messages/run_messages.hpp"

namespace swarm_forage {

/// world/run_info as the follower's description of its run (identity cut at `interval` ticks per sample).
AnnouncedRun describeRun(const RunInfo& info, uint32_t interval);

/// world/noise: the run is no reference from its tick on.
void noiseChanged(RunFollower& follower, const NoiseChange& msg);
/// world/population: the robots out of the swarm this tick (counted into the run's record); with `changed`
/// (rates set by hand) the run is no reference from its tick on.
void followPopulation(RunFollower& follower, const Population& msg);
/// Gives `follower` one recorded message of a run (its topics under any namespace); others are skipped.
/// Throws std::runtime_error for a run topic recorded with another message definition.
void feed(RunFollower& follower, const rosbag::MessageInstance& m);
/// Every message of the bag at `path`, in recorded order; throws std::runtime_error when it is unreadable
/// or its records do not hold together (checkBag: checked before rosbag reads it).
void feedBag(RunFollower& follower, const std::string& path);

}  // namespace swarm_forage
