#include "swarm_forage/core/controllers/forager_batch.hpp"

namespace swarm_forage {

ForagerBatch::ForagerBatch(uint32_t seed, uint32_t first_id, uint32_t count)
    : seed_(seed),
      first_id_(first_id),
      state_(count, 0),
      state_ticks_(count, 0),
      wander_angle_(count, 0.f),
      stalls_(count) {}

void ForagerBatch::prepare(CommandData& out, ControllerStatus& status,
                           const std::vector<std::string>& state_names) const {
  out.first_id = first_id_;
  if (out.size() != count()) out.resize(count());
  status.in_avoidance = 0;
  status.stalled = 0;
  status.tasks = TaskCounts{};
  status.state_names = state_names;
  status.state_counts.assign(state_names.size(), 0);
}

bool ForagerBatch::idle(uint32_t l, const SensorData& s, CommandData& out) {
  const uint32_t i = first_id_ + l;
  if (s.isActive(i)) {
    if (s.events[i] & kJoined) restart(l);
    return false;
  }
  out.left[l] = out.right[l] = 0.f;
  out.request[l] = kNone;
  out.task[l] = kTaskNone;
  return true;
}

void ForagerBatch::restart(uint32_t l) {
  state_[l] = 0;
  state_ticks_[l] = 0;
  wander_angle_[l] = 0.f;
  stalls_.forget(l);
}

void ForagerBatch::finish(uint32_t l, uint64_t tick, const SensorData& s, const WheelSpeeds& w,
                          uint8_t request, CommandData& out, ControllerStatus& status) {
  const uint32_t i = first_id_ + l;
  out.left[l] = w.left;
  out.right[l] = w.right;
  out.request[l] = request;
  ++state_ticks_[l];
  ++status.state_counts[state_[l]];
  status.in_avoidance += s.threatened[i] != 0 ? 1 : 0;
  status.stalled += stalls_.stalled(l, s.x[i], s.y[i], tick);
}

}  // namespace swarm_forage
