#include "swarm_forage/ros/nodes/controller_ros.hpp"
#include "swarm_forage/ros/nodes/node_runner.hpp"

int main(int argc, char** argv) {
  return swarm_forage::runNode<swarm_forage::ControllerRos>(argc, argv, "controller");
}
