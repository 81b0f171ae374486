#include "swarm_forage/ros/runs/run_recorder.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>

#include "swarm_forage/core/run/checkpoint.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

namespace {
const std::string kActive = ".active";

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

void RunRecorder::open(const std::string& path, const std::string& compression, ExistingBag existing) {
  close(false);
  // Unique to this process: two runs writing into one folder never share (or delete) a temporary file.
  active_ = path + "." + std::to_string(::getpid()) + ".active";
  segments_.clear();
  named_ = next_segment_ = 0;
  join_substitute_ = {};
  compression_ = compression;
  try {
    const auto dir = std::filesystem::path(path).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir);
    openActive();
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write the run bag '" + path + "': " + e.what());
  }
  path_ = path;
  existing_ = existing;
  error_.clear();
  open_ = true;
}

void RunRecorder::openActive() {
  bag_.open(active_, BagWriter::compressionNamed(compression_));
  written_ = 0;
}

std::string RunRecorder::segmentName() {
  // Absolute: a resumed process may run in another folder.
  const std::string stem = std::filesystem::absolute(active_.substr(0, active_.size() - kActive.size()))
                               .lexically_normal()
                               .string();
  for (;;) {
    const std::string name = stem + "." + std::to_string(next_segment_++) + ".segment";
    if (!std::filesystem::exists(name)) return name;
  }
}

std::vector<BagSegment> RunRecorder::checkpoint() {
  if (!open_) return {};
  bag_.close();
  open_ = false;  // until the next part is open
  try {
    BagSegment s;
    s.file = segmentName();
    std::filesystem::rename(active_, s.file);
    s.checksum = fileChecksum(s.file, s.size);
    syncFile(s.file);
    segments_.push_back(std::move(s));
    bag_.reopen(active_);  // the same connection ids: close() copies the segments' chunks
    written_ = 0;
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot checkpoint the run bag " + active_ + ": " + e.what());
  }
  open_ = true;
  return segments_;
}

void RunRecorder::verify(const std::vector<BagSegment>& segments) {
  for (const BagSegment& s : segments) {
    uint64_t size = s.bytes.size(), sum = 0;
    if (!s.bytes.empty()) {
      sum = fnv1a64(s.bytes.data(), s.bytes.size());
    } else {
      if (!std::filesystem::exists(s.file))
        throw CheckpointError("its bag segment " + s.file +
                              " is missing (a run that finished from this checkpoint removed it)");
      sum = fileChecksum(s.file, size);
    }
    if (size != s.size)
      throw CheckpointError("its bag segment " + s.file + " has " + std::to_string(size) +
                            " bytes where the checkpoint says " + std::to_string(s.size));
    if (sum != s.checksum)
      throw CheckpointError("its bag segment " + s.file + " was changed (its checksum does not match)");
  }
}

void RunRecorder::removeLeftovers(const std::string& active, const std::vector<BagSegment>& named) {
  std::error_code ec;
  std::filesystem::remove(active, ec);
  if (active.size() <= kActive.size()) return;
  const std::filesystem::path stem = active.substr(0, active.size() - kActive.size());  // PATH.<pid>
  const std::string prefix = stem.filename().string() + ".", suffix = ".segment";
  std::set<std::string> keep;
  for (const BagSegment& s : named) keep.insert(std::filesystem::path(s.file).filename().string());
  const auto dir = stem.has_parent_path() ? stem.parent_path() : std::filesystem::path(".");
  std::vector<std::filesystem::path> leftovers;  // PATH.<pid>.<n>.segment
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0 || keep.count(name))
      continue;
    const std::string n = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (std::all_of(n.begin(), n.end(), [](char c) { return c >= '0' && c <= '9'; }))
      leftovers.push_back(entry.path());
  }
  for (const auto& path : leftovers) std::filesystem::remove(path, ec);
}

void RunRecorder::resume(const std::string& path, const std::string& compression, ExistingBag existing,
                         std::vector<BagSegment> segments, const Substitute& substitute, bool copy) {
  close(false);
  active_ = path + "." + std::to_string(::getpid()) + ".active";
  compression_ = compression;
  segments_.clear();
  named_ = next_segment_ = 0;
  join_substitute_ = {};
  std::vector<std::string> carried;  // segments the checkpoint carried, written out by this process
  try {
    verify(segments);
    const auto dir = std::filesystem::path(path).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir);
    for (BagSegment& s : segments) {
      if (s.bytes.empty()) continue;
      s.file = segmentName();
      carried.push_back(s.file);
      std::ofstream out(s.file, std::ios::binary | std::ios::trunc);
      out.write(s.bytes.data(), static_cast<std::streamsize>(s.bytes.size()));
      out.close();
      if (!out) throw std::runtime_error("cannot write " + s.file);
      syncFile(s.file);
      std::string().swap(s.bytes);
    }
    std::vector<std::string> files;
    for (const BagSegment& s : segments) files.push_back(s.file);
    openActive();
    if (copy) {
      appendBags(files, bag_, substitute);
      for (const std::string& f : carried) std::filesystem::remove(f);
    } else {  // used in place, the segments are joined at close(); this part goes on with their ids
      if (!files.empty()) bag_.adopt(bagConnections(files.back()));
      segments_ = std::move(segments);
      named_ = carried.empty() ? segments_.size() : 0;  // carried ones: no checkpoint file names them
      join_substitute_ = substitute;
    }
  } catch (const CheckpointError&) {
    throw;
  } catch (const std::exception& e) {
    bag_.close();
    std::error_code ec;
    for (const std::string& f : carried) std::filesystem::remove(f, ec);
    segments_.clear();
    throw std::runtime_error("cannot continue the run bag '" + path + "': " + e.what());
  }
  path_ = path;
  existing_ = existing;
  error_.clear();
  open_ = true;
}

void RunRecorder::join(const std::string& tail, const std::atomic<bool>* stop) {
  std::vector<std::string> files;
  for (const BagSegment& s : segments_) files.push_back(s.file);
  files.push_back(tail);
  openActive();
  appendBags(files, bag_, join_substitute_, stop);
  bag_.close();
}

std::string RunRecorder::fail(const std::string& why) {
  const uint64_t reached = bag_.size();  // what the record needed so far: a lower bound of the space it needs
  bag_.abandon();
  open_ = false;
  std::error_code ec;
  std::filesystem::remove(active_, ec);  // an unindexed part frees its space for the next writer
  const std::filesystem::path dir = std::filesystem::absolute(path_, ec).parent_path();
  const auto space = std::filesystem::space(dir, ec);
  const auto size = [](uint64_t bytes) {
    return bytes < (10u << 20) ? std::to_string(bytes >> 10) + " KiB" : std::to_string(bytes >> 20) + " MiB";
  };
  error_ = why + "; the record was not kept (" + active_ + " removed after " + size(reached) +
           ": the run needs more" +
           (ec ? std::string(")") : "; " + size(space.available) + " free in " + dir.string() + ")");
  closed_.clear();
  segments_.clear();
  return error_;
}

std::string RunRecorder::close(bool complete) {
  if (!open_) return "";
  if (!complete && covered()) {
    // A checkpoint holds all of it: the segments stay for resume:=, a NAME_incomplete.bag would repeat them.
    bag_.close();
    open_ = false;
    std::error_code ec;
    std::filesystem::remove(active_, ec);
    error_.clear();
    closed_ = segments_.back().file + " and the segments before it, for resume:=";
    return "";
  }
  // A join whose segments a checkpoint names, with at most world/run_end after them, may stop for a
  // signal (a SLURM time limit): that checkpoint resumes and joins them.
  const bool stoppable = !segments_.empty() && named_ == segments_.size() && written_ <= 1;
  try {
    bag_.close();
  } catch (const std::runtime_error& e) {
    fail(e.what());
    return "";
  }
  open_ = false;
  // The part since the last checkpoint, when the record is in segments.
  std::string tail;
  if (!segments_.empty()) try {
      tail = segmentName();
      std::filesystem::rename(active_, tail);
      join(tail, stoppable ? stop_ : nullptr);
    } catch (const JoinInterrupted&) {
      bag_.close();
      std::error_code ec;
      std::filesystem::remove(active_, ec);
      std::filesystem::remove(tail, ec);
      error_ =
          "interrupted (signal) while joining the bag's segments; they stay for resume:= of their checkpoint";
      closed_.clear();
      return "";
    } catch (const std::exception& e) {
      bag_.close();
      std::error_code ec;
      if (!tail.empty() && std::filesystem::exists(tail)) std::filesystem::remove(active_, ec);
      std::string files;
      for (const BagSegment& s : segments_) files += " " + s.file;
      error_ = "cannot join the record's segments into one bag (" + std::string(e.what()) +
               "); it is kept in" + files + " " + (std::filesystem::exists(tail) ? tail : active_);
      closed_.clear();
      return "";
    }
  // Like `rosbag record`: NAME.bag appears only once it is complete, so a run library never reads
  // a bag that is still being written; an interrupted run says so in its name (and in world/run_end).
  std::string stem = recordName(path_);
  stem.resize(stem.size() - 4);
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
  // The joined record holds every segment; those a checkpoint names stay while the run is unfinished.
  std::error_code ec;
  if (!tail.empty()) std::filesystem::remove(tail, ec);
  for (std::size_t k = complete && why.empty() ? 0 : named_; k < segments_.size(); ++k)
    std::filesystem::remove(segments_[k].file, ec);
  segments_.clear();
  return closed_;
}

std::string RunRecorder::state() const {
  if (open_)
    return "recording " + active_ + " (" + std::to_string(bag_.size() >> 10) + " KiB" +
           (segments_.empty() ? "" : ", after " + std::to_string(segments_.size()) + " segments") + ")";
  if (!error_.empty()) return "not closed: " + error_;
  return closed_.empty() ? "not recording" : "closed " + closed_;
}

std::string recordName(const std::string& path) {
  const bool bag = path.size() > 4 && path.compare(path.size() - 4, 4, ".bag") == 0;
  return bag ? path : path + ".bag";
}

ExistingBag explicitBagPolicy(const std::string& param, const std::string& path, bool overwrite) {
  if (overwrite || path.empty()) return overwrite ? ExistingBag::kReplace : ExistingBag::kRefuse;
  const std::string file = recordName(path);
  if (std::filesystem::exists(file))
    throw ParameterError("~" + param + " '" + path +
                         (file == path ? "'" : "' is recorded as " + file + ", which") +
                         " exists: give a new path, or ~overwrite true to replace it");
  return ExistingBag::kRefuse;
}

}  // namespace swarm_forage
