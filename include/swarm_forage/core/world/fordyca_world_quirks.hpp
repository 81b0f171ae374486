#pragma once
// The world-side quirks of FORDYCA 2019 as ARGoS and FORDYCA compute them (docs/FIDELITY.md, "FORDYCA as
// it ran", (6)-(8)): the foot-bot's motor ground sensors, the light sensor's occlusion ray, and FORDYCA's
// block operation penalties with their deconfliction. Pure geometry and bookkeeping, no world state.
#include <cstdint>
#include <vector>

namespace swarm_forage {

class StateArchive;

// (6) The foot-bot's four motor ground sensors, robot frame (x ahead, y left) [m]: ARGoS footbot_entity.cpp.
constexpr int kMotorGroundSensors = 4;
constexpr double kMotorGroundX[kMotorGroundSensors] = {0.063, -0.063, -0.063, 0.063};
constexpr double kMotorGroundY[kMotorGroundSensors] = {0.0116, 0.0116, -0.0116, -0.0116};
/// No sensor is farther than this from the centre (with room for the rounding of its rotated offset).
constexpr double kMotorGroundReach = 0.0641;
static_assert(kMotorGroundReach * kMotorGroundReach > 0.063 * 0.063 + 0.0116 * 0.0116 + 1e-6,
              "kMotorGroundReach covers every sensor");

/// FORDYCA's reading of the four sensors (each given as the Ground kind of the floor under it, which is
/// what its grey level encodes): a block when all 4 read black, the nest when at least 3 read the nest's
/// grey, a cache when at least 3 read the cache's grey; else the floor.
uint8_t rimGround(const uint8_t kinds[kMotorGroundSensors]);

// (8) Light occlusion. FORDYCA's nest lights stand at these heights [m] (nest.cpp, a rectangular nest:
// the outer two at 5, the centre one at 1); the foot-bot's body is a cylinder of this height, its gripper a
// disc of kGripperRadius on the rim, ahead (ARGoS dynamics2d_footbot_model.cpp).
constexpr double kFordycaLightHeight[3] = {5.0, 1.0, 5.0};
constexpr double kFootBotHeight = 0.146899733;
constexpr double kGripperRadius = 0.01;

/// ARGoS' occlusion test for one shape: the ray from (x, y, 0) (the sensing robot's origin) to the light at
/// (lx, ly, lz) enters the disc of radius r at (cx, cy), seen from above (chipmunk's segment query: the
/// entry parameter t in [0, 1)), at a height t lz within the body's [0, kFootBotHeight].
bool rayEntersBody(double x, double y, double lx, double ly, double lz, double cx, double cy, double r);

/// Whether a foot-bot at (cx, cy) heading `th` of body radius r (its body and its gripper) shadows the ray.
bool footBotShadows(double x, double y, double lx, double ly, double lz, double cx, double cy, double th,
                    double r);

/// How far from the sensing robot, seen from above, a body can shadow a light at horizontal distance d and
/// height lz: the ray has risen above the bodies beyond d x kFootBotHeight / lz.
inline double shadowReach(double d, double lz) { return lz <= kFootBotHeight ? d : d * kFootBotHeight / lz; }

// (7) FORDYCA's temporal_penalty_handler for one kind of block operation (free pick-up or nest drop).
class BlockPenaltyHandler {
 public:
  struct Penalty {
    uint32_t robot;
    int32_t id;  // the block (FORDYCA's penalty id)
    uint32_t penalty;
    uint64_t start;
  };
  void reset(std::size_t n_robots);
  /// deconflict_penalty_finish: the penalty `value` (0 counts as 1) lengthened until no penalty in the list
  /// finishes at the same tick, as FORDYCA's loop does it (it restarts at the list's second entry).
  uint32_t deconflict(uint64_t tick, uint32_t value) const;
  /// penalty_init after the filter: appends robot's penalty.
  void start(uint32_t robot, int32_t id, uint64_t tick, uint32_t value);
  bool serving(uint32_t robot) const { return robot < serving_.size() && serving_[robot] != 0; }
  /// The robot's penalty (it must be serving one).
  const Penalty& of(uint32_t robot) const;
  /// penalty_satisfied: serving and tick - start >= penalty.
  bool satisfied(uint32_t robot, uint64_t tick) const;
  void remove(uint32_t robot);
  std::size_t size() const { return list_.size(); }
  const std::vector<Penalty>& penalties() const { return list_; }  // in start order
  void persist(StateArchive& a);                                   // world_checkpoint.cpp

 private:
  std::vector<Penalty> list_;     // in the order the penalties started (FORDYCA's std::list)
  std::vector<uint8_t> serving_;  // by robot id
};

/// The robot ids in the order ARGoS visits FORDYCA's foot-bots (a std::map by the id "fb<i>": the decimal
/// ids sorted as text, fb0, fb1, fb10, fb100, ...).
std::vector<uint32_t> argosIdOrder(uint32_t n);

}  // namespace swarm_forage
