#pragma once
// Writes a run to a rosbag, tick by tick, in simulated time; closed (and so readable) on every exit path.
#include <ros/time.h>
#include <rosbag/bag.h>

#include <cstdint>
#include <string>
#include <vector>

namespace swarm_forage {

/// Simulated time of a tick: tick * ns_per_tick (what /clock carries).
ros::Time tickTime(uint64_t tick, uint64_t ns_per_tick);

class RunRecorder {
 public:
  ~RunRecorder() { close(false); }
  /// Starts writing `path`.active, chunks compressed with `compression` (one of compressions());
  /// throws std::runtime_error naming the path when it cannot.
  void open(const std::string& path, const std::string& compression = "none");
  static std::vector<std::string> compressions();
  bool isOpen() const { return open_; }
  /// The name the bag gets on close (default: the one given to open()).
  void rename(const std::string& path) { path_ = path; }

  template <typename M>
  void write(const std::string& topic, const ros::Time& stamp, const M& msg) {
    // rosbag rejects time 0; tick 0 is recorded at the earliest time a bag can hold.
    if (open_) bag_.write(topic, stamp < ros::TIME_MIN ? ros::TIME_MIN : stamp, msg);
  }
  /// Closes the bag and gives it its name, NAME.bag, or NAME_incomplete.bag for a run that did not
  /// reach its last tick. `keep_existing`: a file of that name is never replaced; NAME_2.bag, ... is
  /// taken instead. Returns the final path ("" when nothing was open).
  std::string close(bool complete, bool keep_existing = false);
  /// "recording PATH.active (N KiB)", "closed PATH" or "not recording": for /diagnostics.
  std::string state() const;

 private:
  rosbag::Bag bag_;
  std::string active_, path_, closed_;
  bool open_ = false;
};

}  // namespace swarm_forage
