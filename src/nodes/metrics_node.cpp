#include "swarm_forage/ros/nodes/metrics_ros.hpp"
#include "swarm_forage/ros/nodes/node_runner.hpp"

int main(int argc, char** argv) {
  return swarm_forage::runNode<swarm_forage::MetricsRos>(argc, argv, "metrics");
}
