#pragma once
// Writes a run to a rosbag, tick by tick, in simulated time; closed (and so readable) on every exit path.
#include <ros/time.h>
#include <rosbag/bag.h>

#include <cstdint>
#include <string>

namespace swarm_forage {

/// Simulated time of a tick: tick * ns_per_tick (what /clock carries).
ros::Time tickTime(uint64_t tick, uint64_t ns_per_tick);

class RunRecorder {
 public:
  ~RunRecorder() { close(); }
  /// Opens `path`.active for writing (renamed to `path` on close); throws std::runtime_error naming the
  /// path when it cannot.
  void open(const std::string& path);
  bool isOpen() const { return open_; }
  const std::string& path() const { return path_; }

  template <typename M>
  void write(const std::string& topic, const ros::Time& stamp, const M& msg) {
    // rosbag rejects time 0; tick 0 is recorded at the earliest time a bag can hold.
    if (open_) bag_.write(topic, stamp < ros::TIME_MIN ? ros::TIME_MIN : stamp, msg);
  }
  void close();

 private:
  rosbag::Bag bag_;
  std::string path_;
  bool open_ = false;
};

}  // namespace swarm_forage
