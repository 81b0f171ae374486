#include "swarm_forage/ros/tick_gate.hpp"

#include <algorithm>

namespace swarm_forage {

void RangeCoverage::begin(uint32_t n_robots) {
  if (n_robots != n_) senders_.clear();
  n_ = n_robots;
  covered_ = 0;
  answered_.assign(n_robots, 0);
}

bool RangeCoverage::add(uint32_t first, uint32_t count, const std::string& sender) {
  if (count == 0 || first >= n_ || count > n_ - first) return false;
  if (std::any_of(answered_.begin() + first, answered_.begin() + first + count, [](uint8_t a) { return a; }))
    return false;
  std::fill(answered_.begin() + first, answered_.begin() + first + count, 1);
  covered_ += count;
  senders_[first] = {count, sender};
  return true;
}

std::string RangeCoverage::missing() const {
  std::string out;
  for (uint32_t i = 0; i < n_;) {
    if (answered_[i]) {
      ++i;
      continue;
    }
    uint32_t j = i;
    while (j < n_ && !answered_[j]) ++j;
    std::string who;
    for (const auto& [first, entry] : senders_)
      if (first < j && first + entry.first > i && who.find(entry.second) == std::string::npos)
        who += (who.empty() ? "" : ", ") + entry.second;
    out += (out.empty() ? "" : "; ") + std::string("robots [") + std::to_string(i) + ", " +
           std::to_string(j) + ") on " + topic_ +
           (who.empty() ? " (no node has ever answered for them)" : " from " + who);
    i = j;
  }
  return out;
}

}  // namespace swarm_forage
