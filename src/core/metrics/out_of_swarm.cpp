#include "swarm_forage/core/metrics/out_of_swarm.hpp"

#include <algorithm>

#include "swarm_forage/core/run/run_records.hpp"

namespace swarm_forage {

void OutOfSwarm::add(const OutOfSwarm& o) {
  ticks += o.ticks;
  robot_ticks += o.robot_ticks;
  returns += o.returns;
  return_ticks += o.return_ticks;
  open += o.open;
}

std::optional<double> OutOfSwarm::meanOut() const {
  if (ticks == 0) return std::nullopt;
  return robot_ticks / static_cast<double>(ticks);
}

std::optional<double> OutOfSwarm::meanTimeOut() const {
  if (returns == 0) return std::nullopt;
  return return_ticks / static_cast<double>(returns);
}

bool OutOfSwarm::operator==(const OutOfSwarm& o) const {
  return ticks == o.ticks && robot_ticks == o.robot_ticks && returns == o.returns &&
         return_ticks == o.return_ticks && open == o.open;
}

void OutOfSwarmCounter::add(const PopulationRecord& p) {
  if (broken_) return;
  if (p.tick != next_tick_) {
    broken_ = true;
    return;
  }
  ++next_tick_;
  const auto leave = [&](uint32_t id) {
    if (id >= left_.size()) left_.resize(id + 1, -1);
    if (left_[id] < 0) left_[id] = static_cast<int64_t>(p.tick);  // already out: awaiting repair, then dead
  };
  const auto back = [&](uint32_t id) {
    if (id >= left_.size() || left_[id] < 0) return;  // never seen leaving
    ++totals_.returns;
    totals_.return_ticks += static_cast<double>(p.tick - static_cast<uint64_t>(left_[id]));
    left_[id] = -1;
  };
  for (const uint32_t id : p.deaths) leave(id);
  for (const uint32_t id : p.births) back(id);
  for (const uint32_t id : p.malfunctions) leave(id);
  for (const uint32_t id : p.repairs) back(id);
  ++totals_.ticks;
  totals_.robot_ticks += static_cast<double>(p.max_size > p.active ? p.max_size - p.active : 0);
}

std::optional<OutOfSwarm> OutOfSwarmCounter::totals(uint64_t ticks) const {
  if (broken_ || totals_.ticks != ticks || ticks == 0) return std::nullopt;
  OutOfSwarm t = totals_;
  t.open = static_cast<uint64_t>(std::count_if(left_.begin(), left_.end(), [](int64_t v) { return v >= 0; }));
  return t;
}

}  // namespace swarm_forage
