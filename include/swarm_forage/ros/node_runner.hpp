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

template <typename Node>
int runNode(int argc, char** argv, const char* name) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::printf(
          "usage: rosrun swarm_forage %s_node [_PARAM:=VALUE ...] [__name:=NAME]\n"
          "private parameters (~PARAM; any other is refused at start-up; a name ending in / is a section):\n"
          "  %s\n"
          "Defaults and valid ranges: docs/nodes-and-parameters.md; a bad value stops the node with exit "
          "code 2 naming them.\n",
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
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", ros::this_node::getName().c_str(), e.what());
    return 2;
  }
  return code;
}

}  // namespace swarm_forage
