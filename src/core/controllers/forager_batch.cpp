#include "swarm_forage/core/controllers/forager_batch.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "swarm_forage/core/util/lanes_x4.hpp"
#include "swarm_forage/core/util/simd.hpp"

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
      heading_est_(count, 0.0),
      disp_x_(count, 0.0),
      disp_y_(count, 0.0),
      heading_stale_(count, 0) {
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
  heading_stale_[l] = 0;
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
  // With a finite heading the velocity's length is |speed| to a few ulps: only a speed within 1e-9 of the
  // threshold needs the trigonometry (and the heading estimate's atan2) to decide.
  const double speed = std::abs(drive_speed_[l]);
  if (headingFinite(l, i, s)) {
    if (speed < 0.1 * (1 - 1e-9)) return true;
    if (speed > 0.1 * (1 + 1e-9)) return false;
  }
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
  wanders_.resize(n);
  wander_count_ = 0;
}

void ForagerBatch::driveMotion(uint32_t l, Motion m, const SensorData& s, CounterRng& rng, bool slow) {
  motion_[l] = static_cast<uint8_t>(m);
  slow_[l] = slow ? 1 : 0;
  force_[l] = Vec2(0, 0);
  if (motionWanders(m, s, first_id_ + l, slow)) {  // wanderForce(angle, rng, c)'s draw
    wander_rng_[l] = rng.deferNext();
    wanders_[wander_count_++] = l;
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
        prev_x(b.prev_x_.data()),
        prev_y(b.prev_y_.data()),
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
  /// robot() and remember() of l .. l + 3, none of them kStill, in 4 lanes: the same values, without
  /// robot()'s branches (whether a robot's stall anchor moves is a coin flip for the branch predictor).
  SWARM_FORAGE_AVX2 void robots4(uint32_t l, const uint8_t* soft, const WheelSpeeds* wheels,
                                 const WheelSpeeds* direct, const uint8_t* req) {
    const uint32_t i = first + l;
    int32_t r4, s4, t4;
    std::memcpy(&r4, req + l, 4);
    std::memcpy(&s4, soft + l, 4);
    std::memcpy(&t4, threatened + i, 4);
    const __m256i q = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(r4));
    // driven(l): each robot's (left, right) pair is one 64-bit lane.
    const __m256d none = _mm256_castsi256_pd(
        _mm256_cmpeq_epi64(_mm256_cvtepu8_epi64(_mm_cvtsi32_si128(s4)), _mm256_set1_epi64x(kSteerNone)));
    const __m256 w = _mm256_castpd_ps(
        _mm256_blendv_pd(_mm256_loadu_pd(reinterpret_cast<const double*>(wheels + l)),
                         _mm256_loadu_pd(reinterpret_cast<const double*>(direct + l)), none));
    const __m256i even_odd = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
    const __m256 lr = _mm256_permutevar8x32_ps(w, even_odd);  // left 0..3 | right 0..3
    const __m128 wl = _mm256_castps256_ps128(lr), wr = _mm256_extractf128_ps(lr, 1);
    _mm_storeu_ps(left + l, wl);
    _mm_storeu_ps(right + l, wr);
    std::memcpy(request + l, &r4, 4);
    // drive_speed = (left + right) / 2 * 100 where req == kNone and not coasting (x 0.5 is / 2, exactly).
    int32_t c4;
    std::memcpy(&c4, coasting + l, 4);
    const __m256i c = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(c4));
    const __m256i zero = _mm256_setzero_si256();
    const __m256d drive =
        _mm256_castsi256_pd(_mm256_and_si256(_mm256_cmpeq_epi64(q, zero), _mm256_cmpeq_epi64(c, zero)));
    const __m256d speed = _mm256_mul_pd(
        _mm256_mul_pd(_mm256_add_pd(_mm256_cvtps_pd(wl), _mm256_cvtps_pd(wr)), _mm256_set1_pd(0.5)),
        _mm256_set1_pd(100.0));
    _mm256_storeu_pd(drive_speed + l, _mm256_blendv_pd(_mm256_loadu_pd(drive_speed + l), speed, drive));
    std::memset(coasting + l, 0, 4);
    auto* ticks = reinterpret_cast<__m128i*>(state_ticks + l);
    _mm_storeu_si128(ticks, _mm_add_epi32(_mm_loadu_si128(ticks), _mm_set1_epi32(1)));
    for (uint32_t k = l; k < l + 4; ++k) ++counts[state[k]];
    avoiding += static_cast<uint32_t>(__builtin_popcount(
        ~_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_cvtsi32_si128(t4), _mm_setzero_si128())) & 0xf));
    // StallTracker::Arrays::stalled: the anchor moves when unseen, in the future, or over kDistance away.
    const __m128 px = _mm_loadu_ps(x + i), py = _mm_loadu_ps(y + i);
    _mm_storeu_ps(prev_x + l, px);  // remember(l)
    _mm_storeu_ps(prev_y + l, py);
    const __m128 ax = _mm_loadu_ps(stalls.x + l), ay = _mm_loadu_ps(stalls.y + l);
    const __m128 dx = _mm_sub_ps(px, ax), dy = _mm_sub_ps(py, ay);
    const __m128 far = _mm_cmp_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)),
                                  _mm_set1_ps(StallTracker::kDistance * StallTracker::kDistance), _CMP_GT_OQ);
    auto* since_p = reinterpret_cast<__m256i*>(stalls.since + l);
    const __m256i since = _mm256_loadu_si256(since_p);
    const __m256i bias = _mm256_set1_epi64x(static_cast<long long>(1ULL << 63));
    const __m256i now = _mm256_set1_epi64x(static_cast<long long>(tick));
    const __m256i later =
        _mm256_cmpgt_epi64(_mm256_xor_si256(since, bias), _mm256_xor_si256(now, bias));  // tick < since
    const __m256i unseen = _mm256_cmpeq_epi64(since, _mm256_set1_epi64x(-1));
    const __m256i move =
        _mm256_or_si256(_mm256_or_si256(unseen, later), _mm256_cvtepi32_epi64(_mm_castps_si128(far)));
    const __m128 move32 =
        _mm_castsi128_ps(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32(move, even_odd)));
    _mm_storeu_ps(stalls.x + l, _mm_blendv_ps(ax, px, move32));
    _mm_storeu_ps(stalls.y + l, _mm_blendv_ps(ay, py, move32));
    const __m256i anchor = _mm256_blendv_epi8(since, now, move);
    _mm256_storeu_si256(since_p, anchor);
    // tick - since >= kTicks: since <= tick now, so the difference is small and non-negative.
    const __m256i long_still =
        _mm256_cmpgt_epi64(_mm256_sub_epi64(now, anchor), _mm256_set1_epi64x(StallTracker::kTicks - 1));
    stalled += static_cast<uint32_t>(__builtin_popcount(_mm256_movemask_pd(_mm256_castsi256_pd(long_still))));
  }
  /// The position of this tick, for the next tick's heading estimate (idle() leaves it to the finish).
  void remember(uint32_t l) {
    prev_x[l] = x[first + l];
    prev_y[l] = y[first + l];
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
  float *prev_x, *prev_y;
  const StallTracker::Arrays stalls;
  uint32_t avoiding = 0, stalled = 0;
};

void ForagerBatch::finish(uint32_t l, uint64_t tick, const SensorData& s, const WheelSpeeds& w,
                          uint8_t request, CommandData& out, ControllerStatus& status) {
  Finisher f(*this, tick, s, out, status);
  f.robot(l, w, request);
  f.remember(l);
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
  const bool simd = simdEnabled();
  const auto finishOne = [&](uint32_t l) {  // driven(l), through pointers taken once
    if (request[l] == kStill) return;
    f.robot(l, soft[l] == kSteerNone ? direct[l] : wheels[l], request[l]);
    f.remember(l);
  };
  // Whether any of 4 request bytes is kStill (0xff): the classic has-zero-byte test on their complement.
  const auto hasStill = [](int32_t r4) {
    const uint32_t v = ~static_cast<uint32_t>(r4);
    return ((v - 0x01010101u) & ~v & 0x80808080u) != 0;
  };
  std::size_t wander = 0;  // wanders_ is in increasing local index: each strip's are a run of it
  for (uint32_t first = 0; first < n; first += kStrip) {
    const uint32_t end = std::min(n, first + kStrip);
    chooseDrives(first, end, tick, s, out);
    const uint32_t* robots = wanders_.data() + wander;
    const uint32_t* next = robots;
    const uint32_t* const wander_end = wanders_.data() + wander_count_;
    // The strip's wander draws, in a loop without branches: several robots' mix64 chains in flight.
    if (wander_at_tick_)
      for (; next != wander_end && *next < end; ++next)
        draw_[*next] = rngAt(*next, tick).uniform(-c.wander_step, c.wander_step);
    else
      for (; next != wander_end && *next < end; ++next)
        draw_[*next] = wander_rng_[*next].uniform(-c.wander_step, c.wander_step);
    wanderForces(robots, static_cast<std::size_t>(next - robots), wander_angle_.data(), draw_.data(),
                 force_.data(), c);
    wander += static_cast<std::size_t>(next - robots);
    motionForces(motion_.data() + first, slow_.data() + first, s, first_id_ + first, end - first, c,
                 force_.data() + first, soft_.data() + first);
    steerAll(force_.data() + first, soft_.data() + first, wheels_.data() + first, end - first, c.drive);
    uint32_t l = first;
    if (simd)  // groups of 4 with no robot out of the swarm (kStill) in 4 lanes
      for (; l + 4 <= end; l += 4) {
        int32_t r4;
        std::memcpy(&r4, request + l, 4);
        if (!hasStill(r4))
          f.robots4(l, soft, wheels, direct, request);
        else
          for (uint32_t k = l; k < l + 4; ++k) finishOne(k);
      }
    for (; l < end; ++l) finishOne(l);
  }
  f.count(status);
}

}  // namespace swarm_forage
