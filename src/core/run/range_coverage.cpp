#include "swarm_forage/core/run/range_coverage.hpp"

#include <algorithm>

namespace swarm_forage {

namespace {
std::string range(uint32_t lo, uint32_t hi) {
  return "[" + std::to_string(lo) + ", " + std::to_string(hi) + ")";
}
}  // namespace

void RangeCoverage::begin(uint32_t n_robots) {
  if (n_robots != n_) history_.clear();
  n_ = n_robots;
  covered_ = 0;
  owner_.assign(n_robots, -1);
  names_.clear();
}

RangeCoverage::Added RangeCoverage::add(uint32_t first, uint32_t count, const std::string& sender) {
  if (count == 0 || first >= n_ || count > n_ - first) {
    rejection_ = sender + " answers on " + topic_ + " for robots " + range(first, first + count) +
                 ", beyond the swarm of " + std::to_string(n_) + " robots [0, " + std::to_string(n_) + ")";
    return Added::kRejected;
  }
  const auto begin = owner_.begin() + first, end = begin + count;
  const auto taken = std::find_if(begin, end, [](int32_t o) { return o >= 0; });
  if (taken != end) {
    const std::string& other = names_[*taken];
    if (other == sender && std::all_of(begin, end, [&](int32_t o) { return o >= 0 && names_[o] == sender; }))
      return Added::kRepeat;
    // The robots both claim (the overlap of the two ranges), and each node's whole claim.
    const uint32_t lo = static_cast<uint32_t>(taken - owner_.begin());
    uint32_t hi = lo, other_lo = lo, other_hi = lo;
    while (hi < first + count && owner_[hi] == *taken) ++hi;
    while (other_lo > 0 && owner_[other_lo - 1] == *taken) --other_lo;
    while (other_hi < n_ && owner_[other_hi] == *taken) ++other_hi;
    std::pair<std::string, std::string> a{other, range(other_lo, other_hi)},
        b{sender, range(first, first + count)};
    if (b < a) std::swap(a, b);  // the same words whichever answered first
    rejection_ = "robots " + range(lo, hi) + " on " + topic_ + " are claimed by both " + a.first + " (" +
                 a.second + ") and " + b.first + " (" + b.second +
                 "): give each controller node its own range (~first_id, ~count)";
    return Added::kRejected;
  }
  auto name = std::find(names_.begin(), names_.end(), sender);
  if (name == names_.end()) name = names_.insert(names_.end(), sender);
  std::fill(begin, end, static_cast<int32_t>(name - names_.begin()));
  covered_ += count;
  history_[first] = {count, sender};
  return Added::kNew;
}

std::string RangeCoverage::served(uint32_t lo, uint32_t hi) const {
  std::string who;
  for (const auto& [first, entry] : history_)
    if (first < hi && first + entry.first > lo && who.find(entry.second) == std::string::npos)
      who += (who.empty() ? "" : ", ") + entry.second;
  return who;
}

std::string RangeCoverage::missing() const {
  std::string all;  // every range answered so far, to show where a gap lies
  for (const auto& [first, entry] : history_)
    all += (all.empty() ? "" : ", ") + entry.second + " serves " + range(first, first + entry.first);
  std::string out;
  for (uint32_t i = 0; i < n_;) {
    if (owner_[i] >= 0) {
      ++i;
      continue;
    }
    uint32_t j = i;
    while (j < n_ && owner_[j] < 0) ++j;
    const std::string who = served(i, j);
    out += (out.empty() ? "" : "; ") + std::string("robots ") + range(i, j) + " on " + topic_ +
           (!who.empty()  ? " from " + who
            : all.empty() ? " (no node has answered at all)"
                          : ": no node serves them (" + all + ")");
    i = j;
  }
  return out;
}

}  // namespace swarm_forage
