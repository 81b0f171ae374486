#include "swarm_forage/ros/nodes/node_runner.hpp"
#include "swarm_forage/ros/world_node/world_ros.hpp"

int main(int argc, char** argv) { return swarm_forage::runNode<swarm_forage::WorldRos>(argc, argv, "world"); }
