#include "swarm_forage/ros/world_node/world_guard.hpp"

#include <ros/master.h>
#include <ros/ros.h>

#include <algorithm>
#include <set>

namespace swarm_forage {

WorldGuard::WorldGuard(const ros::NodeHandle& nh, std::string world)
    : topics_{nh.resolveName("world/sensors"), nh.resolveName("world/performance")},
      self_(ros::this_node::getName()),
      world_(std::move(world)) {}

std::string WorldGuard::check(bool now) {
  const ros::WallTime t = ros::WallTime::now();
  if (!now && !last_.isZero() && (t - last_).toSec() < 1.0) return "";
  last_ = t;
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = self_;
  // No answer (the master is going away): nothing to say; shutting down is handled elsewhere.
  if (!ros::master::execute("getSystemState", args, result, payload, false)) return "";
  if (payload.getType() != XmlRpc::XmlRpcValue::TypeArray || payload.size() < 1) return "";
  XmlRpc::XmlRpcValue& publishers = payload[0];
  std::set<std::string> others;
  std::string topic;
  for (int i = 0; i < publishers.size(); ++i) {
    XmlRpc::XmlRpcValue& entry = publishers[i];
    if (entry.size() < 2) continue;
    const std::string name = entry[0];
    if (std::find(topics_.begin(), topics_.end(), name) == topics_.end()) continue;
    for (int k = 0; k < entry[1].size(); ++k) {
      const std::string node = entry[1][k];
      if (node != self_ && others.insert(node).second && topic.empty()) topic = name;
    }
  }
  if (others.empty()) return "";
  std::string list;
  for (const auto& o : others) list += (list.empty() ? "" : ", ") + o;
  return "another node publishes " + topic + " in this graph: " + list + " (this world: " + world_ +
         "); one world per graph (a node killed with SIGKILL stays registered: rosnode cleanup)";
}

int WorldGuard::refuse(const std::string& reason, double timeout, const std::atomic<bool>& stop) {
  ROS_FATAL("world: %s: not starting a run", reason.c_str());
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  while (!stop && ros::ok() && ros::WallTime::now() < deadline && !check(true).empty())
    ros::WallDuration(0.2).sleep();
  return 1;
}

}  // namespace swarm_forage
