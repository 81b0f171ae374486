#pragma once
// DPO foraging (docs/design-model.md, Controllers): CRW, plus a per-robot store of the blocks seen in line of
// sight with a decaying pheromone; with a selectable block in the store the robot vectors to the block of
// highest utility, otherwise it explores like CRW. Transport and nest delivery are exactly CRW's.
//
// Interpretations where the design is silent:
// - Store update order each tick: every rho decays once, then the line of sight is merged (first seen or
//   seen more than new_place_distance from the remembered place -> rho = 1.0), then remembered blocks
//   whose position is certainly in sight (certainSight(): the LineOfSight rect, robust to float
//   rounding by 1 mm) but not reported are forgotten. So k ticks after the last (re)set rho = (1-d)^k.
//   The carried block is never recorded; a block is also forgotten when this robot picks it up, and the
//   target when a pick-up at it fails (kBlockVanished or no block under the robot on arrival).
// - The target is selected (argmax of U, blocks closer than exclusion_radius excluded) when vectoring
//   starts or the target is forgotten, and then kept until arrival: re-selecting every tick would drop
//   the target once the robot comes within the exclusion radius. Selection happens in explore only: a
//   robot leaves the nest by wandering (FORDYCA's leaving-nest state) and looks for a block after.
// - Vectoring: force toward the goal of vector_force cm/s (not in the design; = max speed), scaled by
//   distance / slowing_radius inside the slowing radius, plus CRW avoidance outside it. Arrival =
//   distance <= arrival_tolerance; then the robot stops and requests a pick-up if the ground shows a
//   block.
// - Collision = the start of a threat episode while vectoring outside the slowing radius. If it starts
//   less than collision_window ticks after the last tick of the previous one (FORDYCA: "<"), the robot
//   draws a new heading U[0, recovery_max_offset] off its current one (relative), spins toward it at
//   recovery_spin_speed x max_speed (both wheels) until it passes it or recovery_spin_ticks elapse, then
//   drives straight recovery_straight_ticks at recovery_straight_speed x max_speed, ignoring obstacles, then
//   vectors again.
// - Explore -> pick-up on a block under the robot keeps CRW's min_explore_ticks rule.
// - nest_center, los_cell and los_radius must match the world: a run sets them from its world
//   (sharingWorld); the defaults are the 32x16 arena's.
// FORDYCA 2019's controller-side quirks (ForagerBatch::quirks_, docs/FIDELITY.md "FORDYCA as it ran") change
// the recovery angle, the first collision, the arrival force, the heading and the wander when nearly stopped.
// Randomness: one CounterRng(seed, kController, robot id, tick) per robot per tick, drawn in program
// order (recovery heading, then the wander step), so results do not depend on how robots are split.
#include <cstdint>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/block_memory.hpp"
#include "swarm_forage/core/controllers/controller_constants.hpp"
#include "swarm_forage/core/controllers/forager_batch.hpp"

namespace swarm_forage {

struct DpoConfig {
  CrwConfig explore;               // exploration, avoidance, transport and nest delivery constants (crw.yaml)
  Vec2 nest_center{3.2, 8.0};      // nest centre [m]; a run sets it from its world
  double los_cell = 0.2;           // line of sight: cells of this size [m] ...
  int los_radius = 2;              // ... this many cells around the robot's cell (1 m x 1 m)
  double pheromone_initial = 1.0;  // rho when first seen or seen at a new place
  double pheromone_decay = 1e-5;   // rho <- (1 - decay) rho every tick
  double new_place_distance = 0.01;  // m; a block seen farther than this from where remembered moved
  double exclusion_radius = 0.2;     // m; blocks this close to the robot are not selected
  double arrival_tolerance = 0.02;   // m
  double slowing_radius = 0.2;       // m; speed x distance / radius inside it, obstacles ignored there
  double vector_force = 8.0;         // cm/s toward the goal outside the slowing radius (arrival max)
  double slowing_speed_min = 1.0;    // cm/s; the least force inside the slowing radius
  uint32_t collision_window = 300;   // ticks; a second collision within it triggers a new direction
  double recovery_max_offset = 1.0;  // rad; the new direction is U[0, this] off the current heading
  double recovery_heading_tolerance = 0.25;  // rad; spinning stops this close to it ...
  uint32_t recovery_spin_ticks = 10;         // ... or after this many ticks, spinning in place ...
  double recovery_spin_speed = 1.0;          // ... at this fraction of max_speed (the hard-turn speed)
  uint32_t recovery_straight_ticks = 10;     // then straight this long ...
  double recovery_straight_speed = 0.7;      // ... at this fraction of max_speed

  LineOfSight lineOfSight() const { return {los_cell, los_radius}; }
  PheromoneModel pheromone() const { return {pheromone_initial, pheromone_decay, new_place_distance}; }
  void validate() const;  // throws ParameterError naming the field and its range
};

/// DPO's own constants under their YAML names (config/controllers/dpo.yaml; it explores with crw's).
void visitDpoParameters(DpoConfig& c, ConstantVisitor& v);
/// DPO's whole configuration from the constants: crw's exploration, dpo's own, the world's facts if set.
DpoConfig dpoConfig(const ControllerConfigs& configs);

enum class DpoState : uint8_t {
  kExplore,
  kVector,
  kPickup,
  kTransport,
  kNestWander,
  kDrop,
  kLeaveNest,
  kCount
};
const char* dpoStateName(DpoState s);
/// The names of DpoState's values, indexed by state.
const std::vector<std::string>& dpoStateNames();

class DpoBatch : public ForagerBatch {
 public:
  DpoBatch(const DpoConfig& config, uint32_t seed, uint32_t first_id, uint32_t count);
  std::string name() const override { return "dpo"; }
  void step(uint64_t tick, const SensorData& sensors, CommandData& commands,
            ControllerStatus& status) override;

  bool checkpointable() const override;

  DpoState state(uint32_t local) const { return static_cast<DpoState>(state_[local]); }
  const DpoConfig& config() const { return config_; }
  const ObjectMemory& blocks() const { return blocks_; }
  int32_t target(uint32_t local) const { return target_[local]; }  // block vectored to, -1 when none
  /// Turning to a new direction or driving straight after a collision (vector_fsm's recovery).
  bool recovering(uint32_t local) const {
    return recovery_phase_[local] == kSpin || recovery_phase_[local] == kStraight;
  }
  bool avoiding(uint32_t local) const { return recovery_phase_[local] == kAvoid; }

 protected:
  // Vectoring phases (vector_fsm): seeking, avoiding, spinning to a new direction, driving straight.
  enum : uint8_t { kNoRecovery = 0, kSpin = 1, kStraight = 2, kAvoid = 3 };

  /// Switches to state `next` (no-op when already there), restarting the state clock and the vectoring.
  void enter(uint32_t local, DpoState next) { enterState(local, static_cast<uint8_t>(next)); }
  void enterState(uint32_t local, uint8_t next);
  void restart(uint32_t local) override;
  void persistRobot(StateArchive& a, uint32_t local) override;
  /// One tick of the block store from robot i's line of sight. Inline: most robots know and see nothing.
  void observeBlocks(uint32_t local, uint32_t i, const SensorData& s) {
    uint32_t b = 0, e = 0;
    lineOfSightSlice(s.los_block_offset, i, b, e);
    if (blocks_.size(local) != 0 || b != e) updateBlocks(local, i, s, b, e);
  }
  void updateBlocks(uint32_t local, uint32_t i, const SensorData& s, uint32_t b, uint32_t e);
  /// Sets the target to the best selectable block; false (target -1) when there is none.
  bool selectBlock(uint32_t local, uint32_t i, const SensorData& s);
  /// DPO's transitions, one switch over its states: looking for a free block (explore, vector, pick-up),
  /// then CRW's nest delivery (transport .. leave nest).
  void transition(uint32_t local, uint32_t i, const SensorData& s);
  /// Vectoring toward `goal` (map frame) with slowing and collision recovery: the drive (driveWheels ..).
  void vectorTo(uint32_t local, uint32_t i, uint64_t tick, const SensorData& s, const Vec2& goal,
                CounterRng& rng);
  /// The drive (driveWheels ..) and request of state `st`; `goal` is where kVector (and, when set,
  /// kTransport) heads.
  void act(uint32_t local, uint32_t i, uint64_t tick, const SensorData& s, DpoState st, const Vec2* goal,
           CounterRng& rng, uint8_t& request);
  /// The drives of robots [first, end): observe, transition, act (driveAll() calls it strip by strip).
  void chooseDrives(uint32_t first, uint32_t end, uint64_t tick, const SensorData& s,
                    CommandData& out) override;
  /// A collision now is a second one: the last ended less than collision_window ticks ago (or, with
  /// kFirstCollisionAtZero, none yet and FORDYCA's clock tick + 1 is below collision_window).
  bool secondCollision(uint32_t local, uint64_t tick) const;
  /// kCompressedArrival: rcppsw's arrival force as it ran, (m, angle_diff) in the robot frame, so the
  /// heading command is atan2(angle_diff, m) (docs/FIDELITY.md, "FORDYCA as it ran" (4)).
  Vec2 compressedArrival(uint32_t local, uint32_t i, const SensorData& s, const Vec2& to, double magnitude);
  static double distance(const SensorData& s, uint32_t i, const Remembered& r) {
    return (Vec2(r.x, r.y) - Vec2(s.x[i], s.y[i])).norm();
  }

  DpoConfig config_;
  LineOfSight los_;
  PheromoneModel pheromone_;
  ObjectMemory blocks_;
  std::vector<int32_t> target_;
  std::vector<uint64_t> last_collision_;  // end of the last avoidance episode while vectoring; kNever: none
  std::vector<uint8_t> recovery_phase_;
  std::vector<uint32_t> recovery_ticks_;
  std::vector<float> recovery_heading_;
  std::vector<double> arrival_last_;  // kCompressedArrival: rcppsw arrival_force's m_last_angle
  static constexpr uint64_t kNever = ~0ULL;
  static constexpr uint32_t kAhead = 8;  // robots to prefetch ahead: about a memory latency
};

}  // namespace swarm_forage
