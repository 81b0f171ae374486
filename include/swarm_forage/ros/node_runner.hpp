#pragma once
// One main() for every node: parameters are validated at start-up; a bad one ends the node with
// exit code 2 and a message naming it.
#include <ros/ros.h>

#include <atomic>
#include <exception>

namespace swarm_forage {

template <typename Node>
int runNode(int argc, char** argv, const char* name) {
  ros::init(argc, argv, name);
  ros::NodeHandle nh, pnh("~");
  std::atomic<int> code{0};
  try {
    Node node(nh, pnh, [&code](int c) {
      code = c;
      ros::requestShutdown();
    });
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", ros::this_node::getName().c_str(), e.what());
    return 2;
  }
  return code;
}

}  // namespace swarm_forage
