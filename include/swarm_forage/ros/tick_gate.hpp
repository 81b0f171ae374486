#pragma once
// Lockstep bookkeeping: which robot ranges have answered the current tick, and who is missing.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace swarm_forage {

class RangeCoverage {
 public:
  explicit RangeCoverage(std::string topic) : topic_(std::move(topic)) {}
  void begin(uint32_t n_robots);
  /// Records that `sender` answered for robots [first, first + count); false when the range is
  /// out of bounds or already answered (a duplicate is ignored).
  bool add(uint32_t first, uint32_t count, const std::string& sender);
  bool complete() const { return covered_ == n_; }
  /// "robots [a, b) of /controller on swarm/commands" for every robot still missing.
  std::string missing() const;

 private:
  std::string topic_;
  uint32_t n_ = 0, covered_ = 0;
  std::vector<uint8_t> answered_;
  std::map<uint32_t, std::pair<uint32_t, std::string>> senders_;  // first id -> (count, node)
};

}  // namespace swarm_forage
