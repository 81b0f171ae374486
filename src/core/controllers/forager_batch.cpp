#include "swarm_forage/core/controllers/forager_batch.hpp"

#include <algorithm>
#include <cmath>

namespace swarm_forage {

ForagerBatch::ForagerBatch(uint32_t seed, uint32_t first_id, uint32_t count)
    : seed_(seed),
      first_id_(first_id),
      rng_key_(count),
      state_(count, 0),
      state_ticks_(count, 0),
      wander_angle_(count, 0.f),
      stalls_(count),
      drive_speed_(count, 0.0),
      coasting_(count, 0),
      prev_x_(count, 0.f),
      prev_y_(count, 0.f),
      heading_est_(count, 0.0) {
  for (uint32_t l = 0; l < count; ++l)
    rng_key_[l] = CounterRng::idKey(seed, RngStream::kController, first_id + l);
}

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

void ForagerBatch::estimateHeading(uint32_t l, uint32_t i, const SensorData& s) {
  // FORDYCA's loop functions hand every robot its position once per tick (sensing_subsystem::position()
  // keeps the one before): the heading is the displacement's angle, atan2(0, 0) = 0 when standing still.
  heading_est_[l] = std::atan2(static_cast<double>(s.y[i]) - static_cast<double>(prev_y_[l]),
                               static_cast<double>(s.x[i]) - static_cast<double>(prev_x_[l]));
}

bool ForagerBatch::stop(uint32_t l, CommandData& out) {
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
  wander_rng_.resize(n);
  force_.resize(n);
  wheels_.resize(n);
  wanders_.clear();
}

void ForagerBatch::driveMotion(uint32_t l, Motion m, const SensorData& s, CounterRng& rng, bool slow) {
  motion_[l] = static_cast<uint8_t>(m);
  slow_[l] = slow ? 1 : 0;
  force_[l] = Vec2(0, 0);
  if (motionWanders(m, s, first_id_ + l, slow)) {  // wanderForce(angle, rng, c)'s draw
    wander_rng_[l] = rng.deferNext();
    wanders_.push_back(l);
  }
}

// Every array through a local pointer: the byte stores would otherwise make the compiler reload each
// vector's data pointer per robot.
struct ForagerBatch::Finisher {
  Finisher(ForagerBatch& b, uint64_t tick, const SensorData& s, CommandData& out, ControllerStatus& status)
      : tick(tick),
        first(b.first_id_),
        state(b.state_.data()),
        threatened(s.threatened.data()),
        x(s.x.data()),
        y(s.y.data()),
        left(out.left.data()),
        right(out.right.data()),
        request(out.request.data()),
        coasting(b.coasting_.data()),
        drive_speed(b.drive_speed_.data()),
        state_ticks(b.state_ticks_.data()),
        counts(status.state_counts.data()),
        stalls(b.stalls_.arrays()) {}

  void robot(uint32_t l, const WheelSpeeds& w, uint8_t req) {
    const uint32_t i = first + l;
    left[l] = w.left;
    right[l] = w.right;
    request[l] = req;
    // FORDYCA's differential_drive keeps the wheel speeds of its last fsm_drive(); stop() (waiting for a
    // pick-up or drop) and set_wheel_speeds() (coasting) leave them.
    if (req == kNone && !coasting[l])
      drive_speed[l] = (static_cast<double>(w.left) + static_cast<double>(w.right)) / 2.0 * 100.0;
    coasting[l] = 0;
    ++state_ticks[l];
    ++counts[state[l]];
    avoiding += threatened[i] != 0 ? 1 : 0;
    stalled += stalls.stalled(l, x[i], y[i], tick);
  }
  void count(ControllerStatus& status) const {
    status.in_avoidance += avoiding;
    status.stalled += stalled;
  }

  const uint64_t tick;
  const uint32_t first;
  const uint8_t* state;
  const uint8_t* threatened;
  const float *x, *y;
  float *left, *right;
  uint8_t *request, *coasting;
  double* drive_speed;
  uint32_t *state_ticks, *counts;
  const StallTracker::Arrays stalls;
  uint32_t avoiding = 0, stalled = 0;
};

void ForagerBatch::finish(uint32_t l, uint64_t tick, const SensorData& s, const WheelSpeeds& w,
                          uint8_t request, CommandData& out, ControllerStatus& status) {
  Finisher f(*this, tick, s, out, status);
  f.robot(l, w, request);
  f.count(status);
}

void ForagerBatch::driveAll(uint64_t tick, const SensorData& s, const CrwConfig& c, CommandData& out,
                            ControllerStatus& status) {
  // Strips of robots through every stage, not a pass over the whole batch per stage: the forces, wheels
  // and flags one stage leaves are still in L1 for the next. Each robot's operations are the same.
  constexpr uint32_t kStrip = 256;  // a multiple of 4: the 4-lane stages keep their lanes
  const uint32_t n = count();
  Finisher f(*this, tick, s, out, status);
  const uint8_t* request = request_.data();
  const uint8_t* soft = soft_.data();
  const WheelSpeeds* wheels = wheels_.data();
  const WheelSpeeds* direct = direct_.data();
  std::size_t wander = 0;  // wanders_ is in increasing local index: each strip's are a run of it
  for (uint32_t first = 0; first < n; first += kStrip) {
    const uint32_t end = std::min(n, first + kStrip);
    chooseDrives(first, end, tick, s, out);
    const uint32_t* robots = wanders_.data() + wander;
    const uint32_t* next = robots;
    const uint32_t* const wander_end = wanders_.data() + wanders_.size();
    // The strip's wander draws, in a loop without branches: several robots' mix64 chains in flight.
    for (; next != wander_end && *next < end; ++next)
      draw_[*next] = wander_rng_[*next].uniform(-c.wander_step, c.wander_step);
    wanderForces(robots, static_cast<std::size_t>(next - robots), wander_angle_.data(), draw_.data(),
                 force_.data(), c);
    wander += static_cast<std::size_t>(next - robots);
    motionForces(motion_.data() + first, slow_.data() + first, s, first_id_ + first, end - first, c,
                 force_.data() + first, soft_.data() + first);
    steerAll(force_.data() + first, soft_.data() + first, wheels_.data() + first, end - first, c.drive);
    for (uint32_t l = first; l < end; ++l)  // driven(l), through pointers taken once
      if (request[l] != kStill) f.robot(l, soft[l] == kSteerNone ? direct[l] : wheels[l], request[l]);
  }
  f.count(status);
}

}  // namespace swarm_forage
