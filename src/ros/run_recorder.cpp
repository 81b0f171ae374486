#include "swarm_forage/ros/run_recorder.hpp"

#include <filesystem>
#include <stdexcept>

namespace swarm_forage {

ros::Time tickTime(uint64_t tick, uint64_t ns_per_tick) {
  ros::Time t;
  t.fromNSec(tick * ns_per_tick);
  return t;
}

std::vector<std::string> RunRecorder::compressions() { return {"none", "lz4", "bz2"}; }

void RunRecorder::open(const std::string& path, const std::string& compression) {
  close(false);
  try {
    const auto dir = std::filesystem::path(path).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir);
    bag_.open(path + ".active", rosbag::bagmode::Write);
    bag_.setCompression(compression == "bz2"   ? rosbag::compression::BZ2
                        : compression == "lz4" ? rosbag::compression::LZ4
                                               : rosbag::compression::Uncompressed);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write the run bag '" + path + "': " + e.what());
  }
  active_ = path + ".active";
  path_ = path;
  open_ = true;
}

std::string RunRecorder::close(bool complete, bool keep_existing) {
  if (!open_) return "";
  bag_.close();
  open_ = false;
  // Like `rosbag record`: NAME.bag appears only once it is complete, so a run library never reads
  // a bag that is still being written; an interrupted run says so in its name (and in world/run_end).
  std::string stem = path_;
  if (stem.size() > 4 && stem.compare(stem.size() - 4, 4, ".bag") == 0) stem.resize(stem.size() - 4);
  if (!complete) stem += "_incomplete";
  std::string target = stem + ".bag";
  for (int k = 2; keep_existing && std::filesystem::exists(target); ++k)
    target = stem + "_" + std::to_string(k) + ".bag";
  std::error_code ec;
  std::filesystem::rename(active_, target, ec);
  closed_ = ec ? active_ : target;
  return closed_;
}

std::string RunRecorder::state() const {
  if (open_) return "recording " + active_ + " (" + std::to_string(bag_.getSize() >> 10) + " KiB)";
  return closed_.empty() ? "not recording" : "closed " + closed_;
}

}  // namespace swarm_forage
