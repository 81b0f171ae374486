#include "swarm_forage/ros/run_recorder.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

namespace {
/// Gives `from` the name `to` unless `to` exists: a hard link fails on an existing name atomically, so
/// two writers finishing side by side can never replace each other's record. "" or why not.
std::string linkNoClobber(const std::string& from, const std::string& to) {
  if (::link(from.c_str(), to.c_str()) == 0) {
    ::unlink(from.c_str());
    return "";
  }
  const int err = errno;
  if (err == EEXIST) return to + " exists";
  if (err != EPERM && err != ENOTSUP && err != EXDEV) return std::strerror(err);
  // A file system without hard links: the check and the rename are two steps there.
  if (std::filesystem::exists(to)) return to + " exists";
  return ::rename(from.c_str(), to.c_str()) == 0 ? "" : std::strerror(errno);
}
}  // namespace

ros::Time tickTime(uint64_t tick, uint64_t ns_per_tick) {
  ros::Time t;
  t.fromNSec(tick * ns_per_tick);
  return t;
}

std::vector<std::string> RunRecorder::compressions() { return {"none", "lz4", "bz2"}; }

void RunRecorder::open(const std::string& path, const std::string& compression, ExistingBag existing) {
  close(false);
  // Unique to this process: two runs writing into one folder never share (or delete) a temporary file.
  const std::string active = path + "." + std::to_string(::getpid()) + ".active";
  try {
    const auto dir = std::filesystem::path(path).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir);
    bag_.open(active, rosbag::bagmode::Write);
    setCompression(compression);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write the run bag '" + path + "': " + e.what());
  }
  active_ = active;
  path_ = path;
  existing_ = existing;
  error_.clear();
  open_ = true;
}

void RunRecorder::setCompression(const std::string& compression) {
  compression_ = compression;
  bag_.setCompression(compression == "bz2"   ? rosbag::compression::BZ2
                      : compression == "lz4" ? rosbag::compression::LZ4
                                             : rosbag::compression::Uncompressed);
}

std::string RunRecorder::checkpoint() {
  if (!open_) return "";
  bag_.close();
  std::ifstream in(active_, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in) throw std::runtime_error("cannot read back the run bag " + active_ + " for a checkpoint");
  try {
    bag_.open(active_, rosbag::bagmode::Append);
    setCompression(compression_);
  } catch (const std::exception& e) {
    open_ = false;
    throw std::runtime_error("cannot reopen the run bag " + active_ + ": " + e.what());
  }
  return bytes;
}

void RunRecorder::resume(const std::string& path, const std::string& compression, ExistingBag existing,
                         const std::string& bytes, const std::function<void(const std::string&)>& rewrite) {
  close(false);
  const std::string active = path + "." + std::to_string(::getpid()) + ".active";
  try {
    const auto dir = std::filesystem::path(path).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir);
    std::ofstream out(active, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error("cannot write it");
    if (rewrite) rewrite(active);
    bag_.open(active, rosbag::bagmode::Append);
    setCompression(compression);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot continue the run bag '" + path + "': " + e.what());
  }
  active_ = active;
  path_ = path;
  existing_ = existing;
  error_.clear();
  open_ = true;
}

std::string RunRecorder::close(bool complete) {
  if (!open_) return "";
  bag_.close();
  open_ = false;
  // Like `rosbag record`: NAME.bag appears only once it is complete, so a run library never reads
  // a bag that is still being written; an interrupted run says so in its name (and in world/run_end).
  std::string stem = path_;
  if (stem.size() > 4 && stem.compare(stem.size() - 4, 4, ".bag") == 0) stem.resize(stem.size() - 4);
  if (!complete) stem += "_incomplete";
  const ExistingBag policy =
      !complete && existing_ == ExistingBag::kRefuse ? ExistingBag::kNumber : existing_;
  std::string target = stem + ".bag", why;
  if (policy == ExistingBag::kReplace) {
    if (::rename(active_.c_str(), target.c_str()) != 0) why = std::strerror(errno);
  } else {
    why = linkNoClobber(active_, target);
    for (int k = 2; policy == ExistingBag::kNumber && !why.empty() && std::filesystem::exists(target); ++k) {
      target = stem + "_" + std::to_string(k) + ".bag";
      why = linkNoClobber(active_, target);
    }
  }
  error_ = why.empty() ? "" : "cannot name the record " + target + " (" + why + "); it is kept as " + active_;
  closed_ = why.empty() ? target : active_;
  return closed_;
}

std::string RunRecorder::state() const {
  if (open_) return "recording " + active_ + " (" + std::to_string(bag_.getSize() >> 10) + " KiB)";
  if (!error_.empty()) return "not closed: " + error_;
  return closed_.empty() ? "not recording" : "closed " + closed_;
}

ExistingBag explicitBagPolicy(const std::string& param, const std::string& path, bool overwrite) {
  if (overwrite) return ExistingBag::kReplace;
  if (!path.empty() && std::filesystem::exists(path))
    throw ParameterError("~" + param + " '" + path +
                         "' exists: give a new path, or ~overwrite true to replace it");
  return ExistingBag::kRefuse;
}

}  // namespace swarm_forage
