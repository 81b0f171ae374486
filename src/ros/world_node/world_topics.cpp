// world_node as a sink of its runs: the world topics (latched nest, run_info, caches and run_end; robots and
// blocks every ~publish_every ticks while someone listens; performance every tick), /diagnostics and the log.
#include <swarm_forage/Performance.h>

#include "swarm_forage/ros/messages/run_messages.hpp"
#include "swarm_forage/ros/messages/world_messages.hpp"
#include "swarm_forage/ros/world_node/world_ros.hpp"

namespace swarm_forage {

bool WorldRos::wantsSnapshot() const {
  return robots_pub_.getNumSubscribers() > 0 || blocks_pub_.getNumSubscribers() > 0;
}

void WorldRos::begin(const RunDescription& run, const std::string&) {
  const WorldConfig& c = run.world;
  nest_pub_.publish(nestMsg(c.arena));
  frames_->beginRun(run_->world());
  if (!bag_->path().empty())  // the bag sink began first
    ROS_INFO("world: recording run %u to %s%s", run.run, bag_->path().c_str(),
             bag_->outputs().bag_dir.empty() ? "" : " (renamed after the run's identity once tick 0 is in)");
  ROS_INFO("world: run %u: %s, %u robots in %s, seed %u, %lu ticks, %s", run.run, run.name().c_str(),
           c.n_robots, c.arena.name.c_str(), c.seed, static_cast<unsigned long>(run.ticks), run.mode.c_str());
  run_started_ = ros::WallTime::now();
  health_->beginRun(run.run, run.ticks, c.n_robots);
}

void WorldRos::snapshot(uint64_t tick, const SensorData& sensors, const BlockField& blocks) {
  const ros::Time stamp = tickTime(tick, ns_per_tick_);
  robots_pub_.publish(robotsMsg(sensors, tick, stamp));
  blocks_pub_.publish(blocksMsg(blocks, sensors, tick, stamp));
}

void WorldRos::caches(uint64_t tick, const StaticCache& cache) {
  caches_pub_.publish(cachesMsg(cache, tick, tickTime(tick, ns_per_tick_)));
}

void WorldRos::identityFixed(const RunDescription& run) { info_pub_.publish(runInfoMsg(run, ns_per_tick_)); }

void WorldRos::population(const PopulationRecord& p) {
  population_pub_.publish(populationMsg(p, ns_per_tick_));
}

void WorldRos::stepped(const std::vector<StatusRecord>&, const PerformanceRecord& performance) {
  performance_pub_.publish(performanceMsg(performance, ns_per_tick_));
  health_->stepped();
  health_->poll();
}

void WorldRos::end(RunEndRecord& end) {
  end_pub_.publish(runEndMsg(end, ns_per_tick_));
  const std::string where = end.bag.empty() ? "" : "; recorded in " + end.bag;
  const double wall = (ros::WallTime::now() - run_started_).toSec();
  using Status = diagnostic_msgs::DiagnosticStatus;
  health_->phase(end.complete ? "run " + std::to_string(end.run) + " finished" + where
                              : "run " + std::to_string(end.run) + " stopped at tick " +
                                    std::to_string(end.ticks_done) + " (" + end.reason + ")" + where,
                 end.complete ? Status::OK : Status::ERROR);
  health_->reportNow();
  const uint32_t robots = run_->world().config().n_robots;
  if (end.complete)
    ROS_INFO("world: run %u finished: %lu ticks, %lu blocks delivered; %.2f s wall, %.3g robot-ticks/s%s",
             end.run, static_cast<unsigned long>(end.ticks_done),
             static_cast<unsigned long>(run_->world().delivered()), wall,
             wall > 0 ? static_cast<double>(end.ticks_done) * robots / wall : 0.0, where.c_str());
  else
    ROS_ERROR("world: run %u stopped at tick %lu of %lu (%s)%s", end.run,
              static_cast<unsigned long>(end.ticks_done), static_cast<unsigned long>(end.ticks),
              end.reason.c_str(), where.c_str());
}

}  // namespace swarm_forage
