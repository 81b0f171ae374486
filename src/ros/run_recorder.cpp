#include "swarm_forage/ros/run_recorder.hpp"

#include <filesystem>
#include <stdexcept>

namespace swarm_forage {

ros::Time tickTime(uint64_t tick, uint64_t ns_per_tick) {
  ros::Time t;
  t.fromNSec(tick * ns_per_tick);
  return t;
}

void RunRecorder::open(const std::string& path) {
  close();
  try {
    const auto dir = std::filesystem::path(path).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir);
    bag_.open(path + ".active", rosbag::bagmode::Write);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write the run bag '" + path + "': " + e.what());
  }
  path_ = path;
  open_ = true;
}

void RunRecorder::close() {
  if (!open_) return;
  bag_.close();
  open_ = false;
  // Like `rosbag record`: NAME.bag appears only once it is complete, so a run library never reads
  // a bag that is still being written.
  std::error_code ec;
  std::filesystem::rename(path_ + ".active", path_, ec);
}

}  // namespace swarm_forage
