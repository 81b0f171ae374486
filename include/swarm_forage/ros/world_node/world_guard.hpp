#pragma once
// One world per graph. A second world_node (or a bag played into the graph) publishing world/sensors or
// world/performance beside this world would mix its ticks into this run unseen: the controllers would
// answer both, the metrics count both. The master knows every publisher; the guard asks it about once a
// wall second (cheap beside a tick) and names the other publisher and this world.
#include <ros/node_handle.h>

#include <atomic>
#include <string>
#include <vector>

namespace swarm_forage {

class WorldGuard {
 public:
  /// Watches world/sensors and world/performance as `nh` resolves them; `world` names this world in
  /// messages (its private namespace: a nodelet's own name).
  WorldGuard(const ros::NodeHandle& nh, std::string world);
  /// "" while this node is the only publisher of the watched topics, else who else publishes them. Asks
  /// the master at most once per wall second unless `now`.
  std::string check(bool now = false);
  /// A world that finds another at start-up publishes nothing, and stays registered (so that the running
  /// world sees it and stops its run too) until the other is gone or `timeout` has passed; returns 1.
  int refuse(const std::string& reason, double timeout, const std::atomic<bool>& stop);

 private:
  std::vector<std::string> topics_;
  std::string self_, world_;  // the publishers' caller id (a nodelet's manager), and this world's name
  ros::WallTime last_;
};

}  // namespace swarm_forage
