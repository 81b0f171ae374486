#pragma once
// Writes a run to a rosbag, tick by tick, in simulated time; closed (and so readable) on every exit path.
#include <ros/time.h>
#include <rosbag/bag.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace swarm_forage {

/// Simulated time of a tick: tick * ns_per_tick (what /clock carries).
ros::Time tickTime(uint64_t tick, uint64_t ns_per_tick);

/// What close() does when the bag's final name is taken already.
enum class ExistingBag {
  kRefuse,   // an explicit ~bag without ~overwrite: the run's record cannot be closed (an error)
  kReplace,  // ~overwrite true
  kNumber,   // ~bag_dir: NAME_2.bag, NAME_3.bag, ... (runs of one identity side by side)
};

class RunRecorder {
 public:
  ~RunRecorder() { close(false); }
  /// Starts writing a temporary PATH.<pid>.active (unique to this process), chunks compressed with
  /// `compression` (one of compressions()); throws std::runtime_error naming the path when it cannot.
  void open(const std::string& path, const std::string& compression = "none",
            ExistingBag existing = ExistingBag::kRefuse);
  static std::vector<std::string> compressions();
  /// Checkpoints: closes the bag so that it is whole and indexed, returns its bytes and opens it again to
  /// append (rosbag's Append mode), so the run goes on writing the same bag.
  std::string checkpoint();
  /// open() for a resumed run: the temporary file starts as `bytes` (a checkpoint's bag), changed by
  /// `rewrite(path)` when given (a fork's records), and the run appends to it.
  void resume(const std::string& path, const std::string& compression, ExistingBag existing,
              const std::string& bytes, const std::function<void(const std::string&)>& rewrite = {});
  /// The temporary file being written ("" when none).
  const std::string& active() const { return active_; }
  bool isOpen() const { return open_; }
  /// The name the bag gets on close (default: the one given to open()).
  void rename(const std::string& path) { path_ = path; }

  template <typename M>
  void write(const std::string& topic, const ros::Time& stamp, const M& msg) {
    // rosbag rejects time 0; tick 0 is recorded at the earliest time a bag can hold.
    if (open_) bag_.write(topic, stamp < ros::TIME_MIN ? ros::TIME_MIN : stamp, msg);
  }
  /// Closes the bag and gives it its name, NAME.bag, or NAME_incomplete.bag for a run that did not
  /// reach its last tick, without ever replacing another file unless open() was told kReplace (an
  /// incomplete record is numbered rather than refused: it is evidence). Returns the final path ("" when
  /// nothing was open); when the name cannot be taken the bag stays at its temporary name, which is
  /// returned, and error() says why.
  std::string close(bool complete);
  /// Why the last close() could not give the bag its name ("" when it could).
  const std::string& error() const { return error_; }
  /// "recording PATH.<pid>.active (N KiB)", "closed PATH" or "not recording": for /diagnostics.
  std::string state() const;

 private:
  rosbag::Bag bag_;
  std::string active_, path_, closed_, error_;
  void setCompression(const std::string& compression);
  ExistingBag existing_ = ExistingBag::kRefuse;
  std::string compression_ = "none";
  bool open_ = false;
};

/// The policy for an explicit bag path: kReplace with `overwrite`, else kRefuse. Throws ParameterError
/// naming `param` when the file exists and `overwrite` is false.
ExistingBag explicitBagPolicy(const std::string& param, const std::string& path, bool overwrite);

}  // namespace swarm_forage
