#include "swarm_forage/core/controllers/forager_batch.hpp"

#include <cmath>

namespace swarm_forage {

ForagerBatch::ForagerBatch(uint32_t seed, uint32_t first_id, uint32_t count)
    : seed_(seed),
      first_id_(first_id),
      state_(count, 0),
      state_ticks_(count, 0),
      wander_angle_(count, 0.f),
      stalls_(count),
      drive_speed_(count, 0.0),
      coasting_(count, 0),
      prev_x_(count, 0.f),
      prev_y_(count, 0.f),
      heading_est_(count, 0.0) {}

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
    // FORDYCA's loop functions hand every robot its position once per tick (sensing_subsystem::position()
    // keeps the one before): the heading is the displacement's angle, atan2(0, 0) = 0 when standing still.
    if (quirks_.has(Quirk::kHeadingEstimate))
      heading_est_[l] = std::atan2(static_cast<double>(s.y[i]) - static_cast<double>(prev_y_[l]),
                                   static_cast<double>(s.x[i]) - static_cast<double>(prev_x_[l]));
    prev_x_[l] = s.x[i];
    prev_y_[l] = s.y[i];
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
  drive_speed_[l] = 0.0;
  coasting_[l] = 0;
  prev_x_[l] = prev_y_[l] = 0.f;
  heading_est_[l] = 0.0;
}

void ForagerBatch::linearVelocity(uint32_t l, uint32_t i, const SensorData& s, double& vx, double& vy) const {
  // rmath::vector2d(length, radians) is the polar constructor: a negative speed points backwards, and a
  // zero speed gives (+-0, +-0), whose atan2 is 0, -0, pi or -pi by the signs of the heading's cos and sin.
  const double h = heading(l, i, s), v = drive_speed_[l];
  vx = std::cos(h) * v;
  vy = std::sin(h) * v;
}

bool ForagerBatch::nearlyStopped(uint32_t l, uint32_t i, const SensorData& s) const {
  if (!quirks_.has(Quirk::kTransportWander)) return false;
  double vx, vy;
  linearVelocity(l, i, s, vx, vy);
  return std::sqrt(vx * vx + vy * vy) <= 0.1;  // rcppsw vector2::length()
}

void ForagerBatch::beginDrives() {
  const uint32_t n = count();
  motion_.assign(n, kStill);
  soft_.assign(n, kSteerNone);
  direct_.assign(n, WheelSpeeds{});
  slow_.resize(n);
  request_.resize(n);
  draw_.resize(n);
  force_.resize(n);
  wheels_.resize(n);
  wanders_.clear();
}

void ForagerBatch::driveMotion(uint32_t l, Motion m, const SensorData& s, CounterRng& rng, const CrwConfig& c,
                               bool slow) {
  motion_[l] = static_cast<uint8_t>(m);
  slow_[l] = slow ? 1 : 0;
  force_[l] = Vec2(0, 0);
  if (motionWanders(m, s, first_id_ + l, slow)) {  // wanderForce(angle, rng, c)'s draw
    draw_[l] = rng.uniform(-c.wander_step, c.wander_step);
    wanders_.push_back(l);
  }
}

void ForagerBatch::driveAll(const SensorData& s, const CrwConfig& c) {
  const uint32_t n = count();
  wanderForces(wanders_.data(), wanders_.size(), wander_angle_.data(), draw_.data(), force_.data(), c);
  motionForces(motion_.data(), slow_.data(), s, first_id_, n, c, force_.data(), soft_.data());
  steerAll(force_.data(), soft_.data(), wheels_.data(), n, c.drive);
}

void ForagerBatch::finish(uint32_t l, uint64_t tick, const SensorData& s, const WheelSpeeds& w,
                          uint8_t request, CommandData& out, ControllerStatus& status) {
  const uint32_t i = first_id_ + l;
  out.left[l] = w.left;
  out.right[l] = w.right;
  out.request[l] = request;
  // FORDYCA's differential_drive keeps the wheel speeds of its last fsm_drive(); stop() (waiting for a
  // pick-up or drop) and set_wheel_speeds() (coasting) leave them.
  if (request == kNone && !coasting_[l])
    drive_speed_[l] = (static_cast<double>(w.left) + static_cast<double>(w.right)) / 2.0 * 100.0;
  coasting_[l] = 0;
  ++state_ticks_[l];
  ++status.state_counts[state_[l]];
  status.in_avoidance += s.threatened[i] != 0 ? 1 : 0;
  status.stalled += stalls_.stalled(l, s.x[i], s.y[i], tick);
}

}  // namespace swarm_forage
