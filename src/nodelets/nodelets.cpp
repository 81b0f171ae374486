// Every node as a nodelet: the same wrapper classes, loaded into one process.
#include <nodelet/nodelet.h>

#include <memory>
#include <pluginlib/class_list_macros.hpp>

#include "swarm_forage/ros/nodes/controller_ros.hpp"
#include "swarm_forage/ros/nodes/environment_ros.hpp"
#include "swarm_forage/ros/nodes/metrics_ros.hpp"
#include "swarm_forage/ros/nodes/node_runner.hpp"
#include "swarm_forage/ros/world_node/world_ros.hpp"

namespace swarm_forage {

template <typename Node>
class NodeletOf : public nodelet::Nodelet {
 public:
  ~NodeletOf() override {
    node_.reset();
    forgetPrivateParams(private_ns_);
  }

 private:
  void onInit() override {
    private_ns_ = getPrivateNodeHandle().getNamespace();
    try {
      // A node that finishes (end of run with the exit flags, or an error) ends the manager, as
      // required="true" ends a launch of separate processes.
      node_ = std::make_unique<Node>(getNodeHandle(), getPrivateNodeHandle(), [this](int code) {
        if (code != 0) NODELET_ERROR("%s stopped with exit code %d", getName().c_str(), code);
        shutdownAfterFlush(code);
      });
      forgetPrivateParams(private_ns_);
    } catch (const std::exception& e) {
      NODELET_FATAL("%s: %s", getName().c_str(), e.what());
      forgetPrivateParams(private_ns_);
      throw;
    }
  }
  std::unique_ptr<Node> node_;
  std::string private_ns_;
};

using WorldNodelet = NodeletOf<WorldRos>;
using ControllerNodelet = NodeletOf<ControllerRos>;
using EnvironmentNodelet = NodeletOf<EnvironmentRos>;
using MetricsNodelet = NodeletOf<MetricsRos>;

}  // namespace swarm_forage

PLUGINLIB_EXPORT_CLASS(swarm_forage::WorldNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(swarm_forage::ControllerNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(swarm_forage::EnvironmentNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(swarm_forage::MetricsNodelet, nodelet::Nodelet)
