#pragma once
// Writes a run to a rosbag, tick by tick, in simulated time; closed (and so readable) on every exit path.
#include <ros/time.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "swarm_forage/record/bag_append.hpp"

namespace swarm_forage {

/// Simulated time of a tick: tick * ns_per_tick (what /clock carries).
ros::Time tickTime(uint64_t tick, uint64_t ns_per_tick);

/// What close() does when the bag's final name is taken already.
enum class ExistingBag {
  kRefuse,   // an explicit ~bag without ~overwrite: the run's record cannot be closed (an error)
  kReplace,  // ~overwrite true
  kNumber,   // ~bag_dir: NAME_2.bag, NAME_3.bag, ... (runs of one identity side by side)
};

/// A closed part of a run's bag (RunRecorder::checkpoint): a whole, indexed bag file, never written again.
struct BagSegment {
  std::string file;
  uint64_t size = 0, checksum = 0;  // of the file's bytes (fnv1a64), checked on resume
  std::string bytes;                // the file's bytes when a checkpoint carries them (save_at:=), else empty
};

class RunRecorder {
 public:
  ~RunRecorder() { close(false); }
  /// Starts writing a temporary PATH.<pid>.active (unique to this process), chunks compressed with
  /// `compression` (one of BagWriter::compressionNames()); throws std::runtime_error naming the path when it
  /// cannot.
  void open(const std::string& path, const std::string& compression = "none",
            ExistingBag existing = ExistingBag::kRefuse);
  /// Checkpoints: closes what was written since the last one as a segment, PATH.<pid>.<n>.segment
  /// (renamed, checksummed, fsynced), and goes on writing a new one with the same connection ids; returns
  /// every segment of the record so far. Its cost is the segment's, not the record's; close() joins the
  /// segments by copying their chunks as they are.
  std::vector<BagSegment> checkpoint();
  /// The segments checkpoint() returned last are named by a checkpoint file on disk now: an incomplete
  /// close keeps them for its resume.
  void checkpointWritten() { named_ = segments_.size(); }
  /// Nothing was recorded since a checkpoint file that names every segment: an incomplete close leaves the
  /// record to it (no NAME_incomplete.bag; resume:= continues it).
  bool covered() const { return open_ && !segments_.empty() && named_ == segments_.size() && written_ == 0; }
  /// Replacements of messages of the record so far (a resumed or forked run's tick-0 records).
  using Substitute = swarm_forage::Substitute;
  /// Throws CheckpointError when a segment a checkpoint names (not carries) is missing or changed.
  static void verify(const std::vector<BagSegment>& segments);
  /// Removes the files a killed writer (its `active` name) left beside the segments of its checkpoint:
  /// its temporary bag and the segments not in `named` (by file name; a resume records their ticks again).
  static void removeLeftovers(const std::string& active, const std::vector<BagSegment>& named);
  /// open() for a resumed run whose record so far is `segments` (verified; carried ones are written out
  /// as this process's segments). `copy` (a fork): copied into this process's bag with `substitute`
  /// applied, never used in place (their writer may still need them); else used in place (this process's
  /// part goes on with their connection ids), and `substitute` applies when close() joins them.
  void resume(const std::string& path, const std::string& compression, ExistingBag existing,
              std::vector<BagSegment> segments, const Substitute& substitute, bool copy);
  /// A signal's flag: a join that a checkpoint can redo stops when it is set (close()).
  void setStop(const std::atomic<bool>* stop) { stop_ = stop; }
  /// The temporary file being written ("" when none).
  const std::string& active() const { return active_; }
  bool isOpen() const { return open_; }
  /// The name the bag gets on close (default: the one given to open()).
  void rename(const std::string& path) { path_ = path; }

  template <typename M>
  void write(const std::string& topic, const ros::Time& stamp, const M& msg) {
    if (!open_) return;
    // rosbag rejects time 0; tick 0 is recorded at the earliest time a bag can hold.
    try {
      bag_.write(topic, stamp < ros::TIME_MIN ? ros::TIME_MIN : stamp, msg);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fail(e.what()));
    }
    ++written_;
  }
  /// Closes the bag and gives it its name, NAME.bag, or NAME_incomplete.bag for a run that did not
  /// reach its last tick, without ever replacing another file unless open() was told kReplace (an
  /// incomplete record is numbered rather than refused: it is evidence). A record in segments is joined
  /// into one bag first, and its segments removed (but for those a checkpoint names, when incomplete).
  /// An incomplete record covered() by its checkpoint is not joined: its segments stay and "" is returned.
  /// Returns the final path ("" when nothing was open); when the name cannot be taken the bag stays at its
  /// temporary name, which is returned, and error() says why.
  std::string close(bool complete);
  /// Why the last close() could not give the bag its name ("" when it could).
  const std::string& error() const { return error_; }
  /// "recording PATH.<pid>.active (N KiB)", "closed PATH" or "not recording": for /diagnostics.
  std::string state() const;

 private:
  BagWriter bag_;
  std::string active_, path_, closed_, error_;
  std::vector<BagSegment> segments_;  // the record before active_, in order
  std::size_t named_ = 0;             // how many of them a checkpoint file names
  uint64_t written_ = 0;              // messages since the last checkpoint
  unsigned next_segment_ = 0;
  Substitute join_substitute_;  // a resumed run's replacements of its first process's records
  /// A write failed (the disk is full): the partial file is removed, the record closed with error() saying
  /// so; returns that.
  std::string fail(const std::string& why);
  /// Opens active_ for writing, a record of its own.
  void openActive();
  /// A free name for this process's next segment.
  std::string segmentName();
  /// Joins the record: the segments and `tail` (the last part) into a new active_ bag; JoinInterrupted
  /// when `stop` is set.
  void join(const std::string& tail, const std::atomic<bool>* stop);
  const std::atomic<bool>* stop_ = nullptr;
  ExistingBag existing_ = ExistingBag::kRefuse;
  std::string compression_ = "none";  // the record's, and its parts'
  bool open_ = false;
};

/// The file a complete record of `path` is closed into: `path` with ".bag" added when it lacks it.
std::string recordName(const std::string& path);

/// The policy for an explicit bag path: kReplace with `overwrite`, else kRefuse. Throws ParameterError
/// naming `param` when the record's file (recordName) exists and `overwrite` is false.
ExistingBag explicitBagPolicy(const std::string& param, const std::string& path, bool overwrite);

}  // namespace swarm_forage
