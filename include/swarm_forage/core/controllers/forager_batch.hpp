#pragma once
// The bookkeeping every forager batch shares (CRW, DPO, GP-DPO): its robot range, each robot's state,
// state clock and wander angle, the status counted while the batch steps, and what FORDYCA 2019's
// controller-side quirks need kept per robot (docs/FIDELITY.md, "FORDYCA as it ran"): the speed of the
// last drive command (its velocity estimate) and the last position (its heading estimate).
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/controllers/forage_common.hpp"
#include "swarm_forage/core/world/fordyca_quirks.hpp"

namespace swarm_forage {

class ForagerBatch : public ControllerBatch {
 public:
  uint32_t firstId() const { return first_id_; }
  uint32_t count() const { return static_cast<uint32_t>(state_.size()); }
  /// Every robot's persistRobot() in id order (controller_checkpoint.cpp); refused unless checkpointable().
  void persist(StateArchive& a) override;

 protected:
  ForagerBatch(uint32_t seed, uint32_t first_id, uint32_t count);  // every robot in state 0

  /// Resets the command batch and the status for this range; `state_names` are indexed by state.
  void prepare(CommandData& out, ControllerStatus& status, const std::vector<std::string>& state_names) const;
  /// Population dynamics: true when robot `local` is out of the swarm (its command is zero, no request, and
  /// its state does not advance: the caller skips it). A newcomer (Event kJoined) starts afresh (restart).
  /// Its position of this tick is kept for the next heading estimate as it is finished (driveAll, finish).
  bool idle(uint32_t local, const SensorData& s, CommandData& out) {  // inline: once per robot and tick
    const uint32_t i = first_id_ + local;
    if (!s.isActive(i)) return stop(local, out);
    if (s.events[i] & kJoined) restart(local);
    if (quirks_.has(Quirk::kHeadingEstimate)) estimateHeading(local, i, s);
    return false;
  }
  /// Robot `local` as at tick 0: its kind's state forgotten.
  virtual void restart(uint32_t local);
  /// Saves or loads robot `local`'s state; a kind with more state extends it (base first).
  virtual void persistRobot(StateArchive& a, uint32_t local);
  /// Writes robot `local`'s command, advances its state clock, keeps its position and counts it in the
  /// status (a kind that does not batch its drives; driveAll() does it for a batch).
  void finish(uint32_t local, uint64_t tick, const SensorData& s, const WheelSpeeds& w, uint8_t request,
              CommandData& out, ControllerStatus& status);
  /// Robot `local`'s randomness of this tick: CounterRng(seed_, kController, its id, tick), the same bits.
  CounterRng rngAt(uint32_t local, uint64_t tick) const { return CounterRng::atTick(rng_key_[local], tick); }

  // Batched driving: a first pass over the batch chooses each robot's drive (driveWheels, driveForce or
  // driveMotion, after beginDrives) and its request_ (kStill: out of the swarm, idle()), then driveAll()
  // runs the wander forces, the motion forces and the steering, so that several robots' independent
  // sine, square root and atan2 chains are in flight at once (and 4 at a time with AVX2), and finishes
  // each robot that is not kStill: finish() with its driven(l) wheels and request_[l].
  void beginDrives();
  void driveWheels(uint32_t local, const WheelSpeeds& w) {
    motion_[local] = kStill;
    soft_[local] = kSteerNone;
    direct_[local] = w;
  }
  void driveForce(uint32_t local, const Vec2& force, bool soft_only) {  // steer(force, .., soft_only)
    motion_[local] = kStill;
    soft_[local] = soft_only ? kSteerSoft : kSteerFree;
    force_[local] = force;
  }
  /// motionWheels(m, s, i, wander_angle_[local], rng, c, slow) with driveAll()'s c: its wander step is
  /// rng's next draw (driveAll takes it, in a pass where several robots' draws are in flight; rng skips it).
  void driveMotion(uint32_t local, Motion m, const SensorData& s, CounterRng& rng, bool slow = false);
  void driveAll(uint64_t tick, const SensorData& s, const CrwConfig& c, CommandData& out,
                ControllerStatus& status);
  /// A kind may choose its drives strip by strip instead of in a pass before driveAll(): driveAll() calls
  /// this for robots [first, end) just before their drives, while their data is in L1 (default: nothing).
  virtual void chooseDrives(uint32_t /*first*/, uint32_t /*end*/, uint64_t /*tick*/, const SensorData& /*s*/,
                            CommandData& /*out*/) {}
  const WheelSpeeds& driven(uint32_t local) const {
    return soft_[local] == kSteerNone ? direct_[local] : wheels_[local];
  }

  /// The heading the controller steers by: the exact pose, or with kHeadingEstimate FORDYCA's
  /// sensing_subsystem::heading_angle(), atan2 of the displacement between the last two positions.
  double heading(uint32_t local, uint32_t i, const SensorData& s) const {
    if (!quirks_.has(Quirk::kHeadingEstimate)) return static_cast<double>(s.theta[i]);
    materializeHeading(local);
    return heading_est_[local];
  }
  /// FORDYCA's saa_subsystem::linear_velocity(): the polar vector (current_speed, heading) in cm/s, where
  /// current_speed is the mean of the wheel speeds of the last drive command (fsm_drive).
  void linearVelocity(uint32_t local, uint32_t i, const SensorData& s, double& vx, double& vy) const;
  /// With kTransportWander: |linear_velocity()| <= 0.1 (cm/s), FORDYCA's "nearly stopped"; else false.
  bool nearlyStopped(uint32_t local, uint32_t i, const SensorData& s) const;
  /// The wheels of this tick are not a drive command (FORDYCA set_wheel_speeds(), e.g. driving straight
  /// after a new direction): the velocity estimate keeps the last command's speed.
  void coast(uint32_t local) { coasting_[local] = 1; }

  uint32_t seed_;
  uint32_t first_id_;
  std::vector<uint64_t> rng_key_;      // CounterRng::idKey(seed_, kController, id) of each robot
  FordycaQuirks quirks_;               // the controller-side quirks (the kind's constructor sets them)
  std::vector<uint8_t> state_;         // the kind's state enum
  std::vector<uint32_t> state_ticks_;  // ticks spent in the current state
  std::vector<float> wander_angle_;
  StallTracker stalls_;
  std::vector<double> drive_speed_;     // cm/s: mean wheel speed of the last drive command (0 at the start)
  std::vector<uint8_t> coasting_;       // this tick's wheels are not a drive command
  std::vector<float> prev_x_, prev_y_;  // the position one tick ago ((0, 0) at the start, as FORDYCA's)
  // kHeadingEstimate: atan2 of the last displacement, taken when first read (few robots read it: DPO's
  // recovery, transport_wander's speed); heading_stale_: the displacement of this tick is not taken yet.
  mutable std::vector<double> heading_est_;
  std::vector<double> disp_x_, disp_y_;
  mutable std::vector<uint8_t> heading_stale_;
  // Per-tick scratch of the batched drive, by local index (not state: nothing carries over a tick).
  static constexpr uint8_t kStill = 0xff;  // motion_: no motion force (given wheels or force); request_: idle
  std::vector<uint8_t> motion_, slow_, soft_, request_;  // soft_: each robot's SteerMode
  std::vector<uint32_t>
      wanders_;  // the robots that take a wander draw this tick: wanders_[0 .. wander_count_)
  uint32_t wander_count_ = 0;
  std::vector<CounterRng> wander_rng_;  // each wanderer's generator at its wander draw (taken by driveAll)
  bool wander_at_tick_ = false;  // the kind's wander draw is the first of rngAt(l, tick): wander_rng_ unused
  std::vector<double> draw_;
  std::vector<Vec2> force_;
  std::vector<WheelSpeeds> wheels_, direct_;

 private:
  struct Finisher;                              // finish()'s arrays, taken once per batch
  bool stop(uint32_t local, CommandData& out);  // idle()'s robot out of the swarm: zero command, true
  /// idle()'s with kHeadingEstimate: FORDYCA's loop functions hand every robot its position once per tick
  /// (sensing_subsystem::position() keeps the one before): the heading is the displacement's angle,
  /// atan2(0, 0) = 0 when standing still; taken when read (materializeHeading). Inline: every robot, every
  /// tick.
  void estimateHeading(uint32_t local, uint32_t i, const SensorData& s) {
    disp_x_[local] = static_cast<double>(s.x[i]) - static_cast<double>(prev_x_[local]);
    disp_y_[local] = static_cast<double>(s.y[i]) - static_cast<double>(prev_y_[local]);
    heading_stale_[local] = 1;
  }
  /// Whether heading() is finite, without taking it (atan2 of finite displacements is).
  bool headingFinite(uint32_t local, uint32_t i, const SensorData& s) const {
    if (!quirks_.has(Quirk::kHeadingEstimate)) return std::isfinite(s.theta[i]);
    if (heading_stale_[local]) return std::isfinite(disp_x_[local]) && std::isfinite(disp_y_[local]);
    return std::isfinite(heading_est_[local]);
  }
  void materializeHeading(uint32_t local) const {
    if (!heading_stale_[local]) return;
    heading_est_[local] = std::atan2(disp_y_[local], disp_x_[local]);
    heading_stale_[local] = 0;
  }
};

}  // namespace swarm_forage
