#pragma once
// One main() for every node: parameters are validated at start-up; a bad one ends the node with
// exit code 2 and a message naming it.
#include <ros/ros.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>
#include <thread>

#include "swarm_forage/ros/params/known_params.hpp"
#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

/// The roslaunch that started this process (its parent), or 0: started by hand, by rostest or another
/// program.
inline pid_t launcherPid() {
  const pid_t parent = ::getppid();
  std::ifstream in("/proc/" + std::to_string(parent) + "/cmdline", std::ios::binary);
  for (std::string arg; std::getline(in, arg, '\0');)
    if (arg == "roslaunch" || (arg.size() > 10 && arg.compare(arg.size() - 10, 10, "/roslaunch") == 0))
      return parent;
  return 0;
}

/// Ends the node (or the nodelet manager) after a grace period, so that what it published last (final
/// metrics, the run's end, its /rosout lines) leaves its outgoing queues first; ros::shutdown() would drop
/// them. A node that ends its launch (exit_when_done, exit_on_final) with success asks its roslaunch to shut
/// the graph down, as Ctrl-C does, and exits when it is stopped: a required node's own exit would be
/// reported in red as "REQUIRED process [...] has died!". A failure (code != 0) exits, and is reported so.
inline void shutdownAfterFlush(int code) {
  std::thread([code] {
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    const pid_t launcher = code == 0 ? launcherPid() : 0;
    if (launcher > 0 && ::kill(launcher, SIGINT) == 0) {
      // roslaunch stops every node with SIGINT; should it not, the node ends itself after all.
      for (int k = 0; k < 300 && ros::ok(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
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
      const std::string node = std::string(name) + "_node";
      std::printf(
          "usage: rosrun swarm_forage %s [_PARAM:=VALUE ...] [__name:=NAME]\n"
          "private parameters (~PARAM; any other is refused at start-up; a name ending in / is a section):\n"
          "%s"
          "A bad value stops the node with exit code 2, naming the parameter and its valid range.\n",
          node.c_str(), usageTable(tableUsage(static_cast<ParamReader>(readerNamed(node)))).c_str());
      return 0;
    }
  ros::init(argc, argv, name);
  ros::NodeHandle nh, pnh("~");
  std::atomic<int> code{0};
  try {
    Node node(nh, pnh, [&code](int c) {
      code = c;
      shutdownAfterFlush(c);
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
