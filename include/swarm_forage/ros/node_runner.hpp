#pragma once
// One main() for every node: parameters are validated at start-up; a bad one ends the node with
// exit code 2 and a message naming it.
#include <ros/ros.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>
#include <thread>

#include "swarm_forage/ros/known_params.hpp"

namespace swarm_forage {

/// Shuts the node down after a grace period, so that what it published last (final metrics, the run's
/// end, its /rosout lines) leaves its outgoing queues first; ros::shutdown() would drop them.
inline void shutdownAfterFlush() {
  std::thread([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    ros::requestShutdown();
  }).detach();
}

/// A node reads its private parameters once, at start-up, and then deletes them from the master (whether it
/// started or refused them), and again when it ends (its dynamic_reconfigure servers write theirs back): a
/// node started later under the same name, by hand or by a launch, never runs with an earlier node's
/// parameters (its bag, noise, condition or constants), only with those it is given.
inline void forgetPrivateParams(const std::string& private_ns) {
  if (!private_ns.empty() && ros::isInitialized()) ros::param::del(private_ns);
}

template <typename Node>
int runNode(int argc, char** argv, const char* name) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::printf(
          "usage: rosrun swarm_forage %s_node [_PARAM:=VALUE ...] [__name:=NAME]\n"
          "private parameters (~PARAM; any other is refused at start-up; a name ending in / is a section):\n"
          "  %s\n"
          "Defaults and valid ranges: docs/nodes-and-parameters.md; a bad value stops the node with exit code 2 naming them.\n",
          name, joinNames(Node::parameterNames()).c_str());
      return 0;
    }
  ros::init(argc, argv, name);
  ros::NodeHandle nh, pnh("~");
  std::atomic<int> code{0};
  try {
    Node node(nh, pnh, [&code](int c) {
      code = c;
      shutdownAfterFlush();
    });
    forgetPrivateParams(pnh.getNamespace());
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", ros::this_node::getName().c_str(), e.what());
    forgetPrivateParams(pnh.getNamespace());
    return 2;
  }
  forgetPrivateParams(pnh.getNamespace());
  return code;
}

}  // namespace swarm_forage
