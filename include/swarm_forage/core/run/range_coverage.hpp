#pragma once
// Lockstep bookkeeping: which robot ranges have answered the current tick, from whom, and what is
// wrong with a split of the swarm across nodes (ranges claimed twice, gaps, ranges beyond the swarm).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace swarm_forage {

class RangeCoverage {
 public:
  enum class Added {
    kNew,      // a range nobody has answered for this tick
    kRepeat,   // the same sender again for the same range (a re-offered tick): ignored
    kRejected  // overlaps another sender's range, or lies beyond the swarm: rejection() says how
  };
  explicit RangeCoverage(std::string topic) : topic_(std::move(topic)) {}
  void begin(uint32_t n_robots);
  /// Records that `sender` answered for robots [first, first + count).
  Added add(uint32_t first, uint32_t count, const std::string& sender);
  bool complete() const { return covered_ == n_; }
  /// Distinct senders that answered this tick.
  std::size_t senders() const { return names_.size(); }
  /// Why the last kRejected range was rejected, naming both nodes and the robot ids concerned:
  /// "robots [32, 64) on swarm/commands are claimed by both /a ([0, 64)) and /b ([32, 64)): ...".
  const std::string& rejection() const { return rejection_; }
  /// Every robot range still missing this tick, e.g. "robots [30, 32) on swarm/commands: no node
  /// serves them (/a serves [0, 30), /b serves [32, 64))" or "robots [0, 64) on swarm/commands from /a".
  std::string missing() const;

 private:
  std::string served(uint32_t lo, uint32_t hi) const;  // who has ever served robots in [lo, hi)
  std::string topic_;
  uint32_t n_ = 0, covered_ = 0;
  std::vector<int32_t> owner_;                                    // robot -> index into names_, -1: none
  std::vector<std::string> names_;                                // this tick's senders
  std::map<uint32_t, std::pair<uint32_t, std::string>> history_;  // first id -> (count, node), all ticks
  std::string rejection_;
};

}  // namespace swarm_forage
