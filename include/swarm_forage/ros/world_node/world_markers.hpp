#pragma once
// world/markers: what rviz draws of the world. One marker per kind of thing (walls, nest, lights, cubes,
// ramps, the cache and its count), one SPHERE_LIST per robot class and one CUBE_LIST per GP-DPO task, so
// that 16,384 robots are seven markers, not 16,384.
#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include <cstdint>

#include "swarm_forage/core/world/sensing.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

/// The robot classes world/markers colours (ns "robots", id = class): what the world itself knows of
/// each robot, first match wins.
enum class RobotClass : uint8_t { kCarrying = 0, kAvoiding = 1, kInNest = 2, kExploring = 3, kCount = 4 };
RobotClass robotClass(const SensorData& s, uint32_t i);
/// Its colour, RGB in [0, 1]: carrying orange, avoiding red, in the nest green, exploring light blue.
std_msgs::ColorRGBA robotClassColour(RobotClass c);

/// GP-DPO's tasks (ns "tasks", id = the task, CommandData::task): a square on each robot, generalist
/// white, harvester magenta, collector dark blue. Robots without a task (CRW, DPO) have none.
constexpr uint8_t kTasksShown = 3;
std_msgs::ColorRGBA taskColour(uint8_t task);

/// Fills `out` (frame `map`, stamped `stamp`) from the world, this tick's readings and the robots' latest
/// commands (their tasks); reuses its storage.
void paintMarkers(const World& world, const SensorData& sensors, const CommandData& commands,
                  const ros::Time& stamp, visualization_msgs::MarkerArray& out);

/// world/markers at most `rate` a wall second (0: never), built only while someone subscribes.
class MarkerPublisher {
 public:
  MarkerPublisher(ros::NodeHandle& nh, double rate);
  void publish(const World& world, const SensorData& sensors, const CommandData& commands,
               const ros::Time& stamp);
  uint64_t built() const { return built_; }    // none while nobody subscribes
  double seconds() const { return seconds_; }  // wall time the last one took to build and publish

 private:
  ros::Publisher pub_;
  double rate_;
  visualization_msgs::MarkerArray markers_;  // refilled in place
  ros::WallTime last_;
  uint64_t built_ = 0;
  double seconds_ = 0;
};

}  // namespace swarm_forage
