#pragma once
// The simulated world: arena, nest, blocks and robots' bodies; motion, collisions, sensing,
// pick-up/drop execution and block respawn. Deterministic for one seed, bit-identical for any thread
// count (setThreads).
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/core/world/blocks.hpp"
#include "swarm_forage/core/world/config.hpp"
#include "swarm_forage/core/world/fordyca_world_quirks.hpp"
#include "swarm_forage/core/world/population.hpp"
#include "swarm_forage/core/world/sensing.hpp"
#include "swarm_forage/core/world/sight_index.hpp"
#include "swarm_forage/core/world/spatial_grid.hpp"
#include "swarm_forage/core/world/static_cache.hpp"
#include "swarm_forage/core/world/throttling.hpp"

namespace swarm_forage {

class StateArchive;

/// Robot bodies, structure-of-arrays.
struct RobotBodies {
  std::vector<double> x, y, theta;
  std::vector<int32_t> carried;         // block id, -1 when none
  std::vector<uint8_t> events;          // what was executed in the last step (Event flags)
  std::vector<uint8_t> last_request;    // the request of the last step ...
  std::vector<uint64_t> request_since;  // ... and the tick it was first made (serialised block operations,
                                        // manipulation time)
  std::size_t size() const { return x.size(); }
};

struct StepResult {
  uint32_t delivered = 0;  // blocks dropped in the nest this step
};

class World {
 public:
  /// Validates the configuration (ParameterError) and places robots and blocks.
  explicit World(const WorldConfig& config);

  /// Fresh run with another seed and swarm size (validated like the constructor).
  void reset(uint32_t seed, uint32_t n_robots);

  /// Sensor readings for the current tick: the truth (what is recorded and drawn). With sensor noise,
  /// what the robots perceive is perceived(out).
  void sense(SensorData& out);
  /// What the controllers get: the readings of the last sense() with the sensor noise (config().noise);
  /// `sensed` itself, its argument, when no sensor is noisy.
  const SensorData& perceived(const SensorData& sensed) const {
    return config_.noise.sensorsOn() ? perceived_ : sensed;
  }
  /// Changes the noise from the next sense() and step() on (validated: ParameterError, nothing changes).
  void setNoise(const SaaNoise& noise);

  /// Executes the requests, integrates motion for one tick, respawns delivered blocks and, with population
  /// dynamics, carries out the tick's deaths, births, malfunctions and repairs (world_population.cpp).
  /// `commands` must cover every robot. `throttle` is the condition V and its target: carry_speed slows
  /// robots that carry a block, speed x (1 - V); speed slows every robot so; manipulation_time holds a
  /// pick-up or drop until it has been requested for max(0, V) x kMaxManipulationSeconds (a plain number
  /// is V on carry_speed). `tasks` (GP-DPO) drives the static cache's re-creation.
  StepResult step(const CommandData& commands, Throttling throttle, const TaskCounts& tasks = {});

  /// Threads for sensing and motion (0: one per core), or a pool shared with the controllers. Results do
  /// not depend on the thread count.
  void setThreads(unsigned threads);
  void setPool(std::shared_ptr<WorkerPool> pool) { pool_ = std::move(pool); }
  unsigned threads() const { return pool_->threads(); }

  /// Test hook: puts robot i at (x, y) with heading theta (no overlap check).
  void setPose(uint32_t i, double x, double y, double theta);

  uint64_t tick() const { return tick_; }
  uint64_t delivered() const { return cumulative_; }
  uint32_t carrying() const;
  const WorldConfig& config() const { return config_; }
  const RobotBodies& robots() const { return robots_; }
  const BlockField& blocks() const { return blocks_; }
  const StaticCache& cache() const { return cache_; }
  const PopulationDynamics& population() const { return population_; }
  /// A live change of the population rates (world_node's dynamic_reconfigure, realtime mode): validated as
  /// at start-up (ParameterError); refused for a run without population dynamics.
  void setPopulationRates(const PopulationConfig& rates);
  /// Whether robot i takes part (always, without population dynamics).
  bool active(std::size_t i) const { return !population_.enabled() || population_.activeMask()[i] != 0; }
  bool overlapFree() const;  // no active robot overlaps another one or leaves the arena
  /// With the light_occlusion quirk: how many (robot, light) pairs the last sense() found shadowed.
  uint64_t shadowedLights() const { return shadowed_lights_; }
  /// ... and by robot id, the lights shadowed (bit l for light l).
  const std::vector<uint8_t>& shadowMasks() const { return shadow_masks_; }
  /// With the block_penalties quirk: FORDYCA's penalty list of free pick-ups (the tests read it).
  const BlockPenaltyHandler& pickupPenalties() const { return pickup_penalties_; }
  /// Saves or loads the persistent state between two ticks (world_checkpoint.cpp): bodies, blocks, cache,
  /// population, penalties, noise, tick and counters. Loading needs a world of the same configuration;
  /// the grid, slots and bands are rebuilt by the next tick.
  void persist(StateArchive& a);

 private:
  void placeRobots();
  /// The active mask, or nullptr without population dynamics (every robot active).
  const uint8_t* activeMask() const {
    return population_.enabled() ? population_.activeMask().data() : nullptr;
  }
  /// The tick's population events on bodies and blocks (world_population.cpp).
  void populationStep();
  /// Puts robot i, joining (born: `rejoin` false) or repaired, where the authors' code puts it.
  bool placeJoining(uint32_t i, bool rejoin);
  /// A robot leaving the swarm drops what it carries where it stands.
  void leave(uint32_t i);
  void ensureGrid();
  /// With serialize_block_ops: the robots whose pick-up and nest drop may finish this tick (-1: none).
  std::pair<int32_t, int32_t> servedBlockOps(const CommandData& commands);
  /// kPickup or kDrop when robot i's request is a free-block pick-up or nest drop the world can execute
  /// now (what serialize_block_ops queues); kNone otherwise.
  uint8_t serializedOp(uint32_t i, uint8_t request) const;
  static constexpr std::size_t kChunk = 1024;  // robots (ids or slots) per parallel task
  static constexpr int kChainBodies = 8;       // (9): at most this many bodies move in one push
  static std::size_t chunks(std::size_t n);
  /// The indices [begin, end) of task `chunk` of n.
  static std::pair<std::size_t, std::size_t> chunkSpan(std::size_t chunk, std::size_t n) {
    return {chunk * kChunk, std::min(n, (chunk + 1) * kChunk)};
  }
  struct NearBody {
    double x, y, d2;  // a body's centre in the robot frame, and its squared distance
  };
  // One robot's obstacle and light readings, by slot before they go to SensorData by id: 16 bytes, one
  // cache line to fetch in that scattered copy. The lights are here only with light_occlusion (bodies in
  // the grid shadow them); else senseIds puts them in SensorData, as it does the pose and the ground.
  struct alignas(16) Reading {
    float obstacle_x, obstacle_y, light_x, light_y;
  };
  /// A world-frame vector (lx, ly) in the frame of a robot whose heading is (hx, hy) = (cos, sin).
  static void toRobotFrame(double hx, double hy, double lx, double ly, float& fx, float& fy) {
    fx = static_cast<float>(hx * lx + hy * ly);
    fy = static_cast<float>(-hy * lx + hx * ly);
  }
  void senseRobot(uint32_t slot, std::vector<NearBody>& near);  // world_sensing.cpp
  /// What robots [first, end) sense without the grid, by id straight into `out`: pose, events, carried
  /// block, ground and, without light_occlusion, the lights (world_sensing.cpp).
  void senseIds(std::size_t first, std::size_t end, SensorData& out) const;
  /// Moves every robot (world_motion.cpp); speeds of carriers are multiplied by `carrier_scale`, of the
  /// others by `other_scale`.
  void moveAll(const CommandData& commands, double carrier_scale, double other_scale);
  /// Fills perceived_ from the truth `sensed` with the sensor noise (world_sensing.cpp).
  void perceive(const SensorData& sensed);
  /// The commands after the wheel noise (noisy_commands_).
  const CommandData& wheelNoise(const CommandData& commands);
  /// Records each robot's request and the tick it was first made (RobotBodies::request_since).
  void trackRequests(const CommandData& commands);
  static int bandRows(const WorldConfig& c, double cell);
  /// This tick's grid, bands and slot order (serial: sense() runs senseIds beside it), then the bodies
  /// copied to their slots.
  void buildGrid();
  void copyToSlots();
  /// After buildGrid(): the bodies copied to slot order, and this tick's grid valid.
  void slotGrid();
  /// Robot `slot`'s commanded step (step_x_, step_y_) and new heading (step_th_) for these wheel speeds.
  void commandedStep(uint32_t slot, double left, double right);
  /// Takes robot `slot`'s commanded step as far as the bodies around let it (a robot alone moves in
  /// moveAll's slot pass instead).
  void move(uint32_t slot);
  bool fits(uint32_t slot, double x, double y) const;  // slots: see sx_
  /// Quirk (9) dynamics2d_contacts (world_contacts.cpp): the robot in `slot`, blocked moving by (dx, dy),
  /// pushes the bodies ahead of it as ARGoS' force-limited drives would; true when it moved any, and then
  /// (fx, fy) is the step that follows them.
  bool pushChain(uint32_t slot, double dx, double dy, double& fx, double& fy);
  /// Each robot's commanded displacement this tick and what pushes may still move it (by slot), for (9).
  void prepareContacts(const CommandData& commands, double scale, double other_scale);
  /// The slot of the robot overlapping most with the one in `slot` placed at (x, y); -1 when none.
  int32_t blocker(uint32_t slot, double x, double y) const;
  /// The ground at (x, y): nest, then cache, then a free block, else floor. Inline, as groundFor: every
  /// robot reads it every tick.
  uint8_t groundAt(double x, double y) const {
    if (nest_.contains(x, y)) return kNest;
    if (cache_.contains(x, y)) return kCacheGround;
    return blocks_.blockAt(x, y) >= 0 ? kBlockGround : kFloor;
  }
  // FORDYCA's quirks on the world side (world_quirks.cpp).
  /// The ground robot i (or a slot's body) at (x, y) heading th reads: at the centre, or with the
  /// rim_ground_sensors quirk FORDYCA's rule over the foot-bot's four motor ground sensors (rimGroundFor).
  uint8_t groundFor(double x, double y, double th) const {
    if (!config_.quirks.has(Quirk::kRimGroundSensors)) return groundAt(x, y);
    // Most robots are far from the nest, the cache and every block: their sensors all read the floor.
    const double x0 = x - kMotorGroundReach, x1 = x + kMotorGroundReach;
    const double y0 = y - kMotorGroundReach, y1 = y + kMotorGroundReach;
    // No branches in the test: robots along the nest's edges would mispredict them.
    const auto apart = [&](const Rect& r) {
      return (x1 < r.min_x) | (x0 > r.max_x) | (y1 < r.min_y) | (y0 > r.max_y);
    };
    if (apart(nest_) && (!cache_.exists() || apart(cache_.area())) && !blocks_.nearBlock(x, y)) return kFloor;
    return rimGroundFor(x, y, th);
  }
  uint8_t rimGroundFor(double x, double y, double th) const;
  /// Whether a drop by robot i is a nest drop: the centre in the nest, or in_nest by the rim sensors.
  bool dropsInNest(std::size_t i) const;
  // light_occlusion (light_occlusion.cpp).
  /// The lights in the mask `search` that a body shadows from the robot in `slot` (light l d[l] away
  /// along (ux[l], uy[l])), as a mask.
  unsigned searchShadows(uint32_t slot, unsigned search, const double* d, const double* ux,
                         const double* uy) const;
  /// Before the sensing: the neighbour grid's occupied cells in shadow_bits_, the robots that trace their
  /// lights in traced_. After it, clearShadowCells.
  void prepareShadows();
  void clearShadowCells();
  /// block_penalties: FORDYCA's pick-up and nest drop interactors, robots in ARGoS' order; finishes the
  /// operations whose penalty is served and marks in penalised_ every robot whose request they took.
  void penaltyStep(const CommandData& commands, uint64_t value, StepResult& result);
  // Line of sight (line_of_sight.cpp): a chunk's lists, where they go, and their copy into place.
  void gatherSight(std::size_t chunk);
  void layOutSight(SensorData& out);
  void copySight(std::size_t chunk, SensorData& out) const;

  WorldConfig config_;
  Rect nest_;  // config_.arena.nest(), not recomputed by every ground look-up
  RobotBodies robots_;
  BlockField blocks_;
  StaticCache cache_;
  PopulationDynamics population_;
  /// One sensing task's line-of-sight lists (robot order), joined into SensorData afterwards.
  struct SightChunk {
    std::vector<uint32_t> block_end, cache_end, cache_blocks;
    std::vector<int32_t> block_id, cache_id, scratch;
    std::vector<float> block_x, block_y, cache_x, cache_y;
    std::size_t block_at = 0, cache_at = 0;  // where they start in the joined lists
    void clear();
  };

  std::shared_ptr<WorkerPool> pool_ = std::make_shared<WorkerPool>(1);
  std::vector<Vec2> rays_;  // proximity ray directions (robot frame)
  // The same by coordinate, padded with zeros to a multiple of 4 (the 4-lane path).
  std::vector<double> ray_x_, ray_y_;
  Vec2 lights_[ArenaConfig::kLights];
  // A cache line of its own: workers write it concurrently.
  struct alignas(64) WorkerScratch {
    std::vector<NearBody> near;  // sense()'s neighbours
    // The 4-lane path's neighbours by coordinate (with 4 spare).
    std::vector<double> near_x, near_y, near_d2;
  };
  /// senseRobot for slots [first, end), headings, neighbours and rays 4 at a time
  /// (sensing_x4.cpp): the same readings, bit for bit; only when simdEnabled().
  void senseSlotsX4(std::size_t first, std::size_t end, WorkerScratch& scratch);
  /// With light_occlusion: the lights a body shadows from robot `slot`, and the sum of unit vectors to
  /// the others (map frame; light_occlusion.cpp).
  void shadowedLights(uint32_t slot, double& light_x, double& light_y, uint8_t& shadowed) const;
  /// ... for a robot that traces them this tick; else NaN, "not sensed" (its controller does not read them).
  /// Inline: called for every robot.
  void occludedLights(uint32_t slot, double& light_x, double& light_y, uint8_t& shadowed) const {
    if (traced_[slot]) return shadowedLights(slot, light_x, light_y, shadowed);
    light_x = light_y = std::numeric_limits<double>::quiet_NaN();
    shadowed = 0;
  }
  /// The reading of the robot at `slot` (both sensing paths): obstacle and light in its frame; threat,
  /// shadowed lights and (rim_ground_sensors) ground. Inline: called for every robot.
  void storeReading(uint32_t slot, double hx, double hy, bool threat, double best_x, double best_y, double lx,
                    double ly, uint8_t shadowed, uint8_t ground) {
    float fx, fy;
    toRobotFrame(hx, hy, lx, ly, fx, fy);
    readings_[slot] = Reading{static_cast<float>(best_x), static_cast<float>(best_y), fx, fy};  // one store
    sense_flags_[slot] = static_cast<uint8_t>((threat ? 1 : 0) | shadowed << 1 | ground << 4);
  }
  /// storeReading for a robot that does not trace its lights: NaN for them, "not sensed" (the quiet NaN
  /// that turning occludedLights' NaN by a heading gives).
  void storeUntraced(uint32_t slot, bool threat, double best_x, double best_y, uint8_t ground) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    readings_[slot] = Reading{static_cast<float>(best_x), static_cast<float>(best_y), nan, nan};
    sense_flags_[slot] = static_cast<uint8_t>((threat ? 1 : 0) | ground << 4);
  }
  /// With rim_ground_sensors the ground is read by slot, with the sensing (neighbours one after the other:
  /// the same look-ups and branches), into sense_flags_; else senseIds reads it by id.
  uint8_t slotGround(uint32_t slot) const {
    return config_.quirks.has(Quirk::kRimGroundSensors) ? groundFor(sx_[slot], sy_[slot], sth_[slot]) : 0;
  }
  std::vector<WorkerScratch> scratch_;
  std::vector<SightChunk> los_;  // per sensing task
  SightIndex sight_;             // this tick's, built before the tasks
  SensorData perceived_;         // with sensor noise: what the controllers get
  CommandData noisy_commands_;   // with wheel noise: what the wheels do
  std::vector<uint8_t> pushed_;  // by slot: pushed by another robot this tick (at most once)
  // Quirk (9), by slot: the commanded displacement this tick, and how far pushes may still move the body.
  std::vector<double> want_x_, want_y_, push_left_;
  // By slot: each robot's commanded step and heading this tick (they depend on its own pose only).
  std::vector<double> step_x_, step_y_, step_th_;
  // Tick-start bodies sorted by grid cell: slot s holds robot grid_.order()[s], robot i sits in slot
  // grid_.rank()[i]. The grid's sorted positions are slots; moveAll moves these copies, band by band
  // (bands_[parity]: slot ranges of bands of band_rows_ grid rows).
  int band_rows_ = 6;
  std::vector<double> sx_, sy_, sth_;
  std::vector<Reading> readings_;  // by slot
  // By slot: bit 0 threatened, bits 1 to 3 the lights shadowed (light_occlusion), bits 4 and 5 the ground
  // (rim_ground_sensors); a byte apart from the readings, which stay 16 bytes.
  std::vector<uint8_t> sense_flags_;
  std::vector<double> nearest2_;  // by slot: squared distance to the nearest body sense() saw
  bool clearance_valid_ = false;  // nearest2_ is this tick's
  std::array<std::vector<std::pair<uint32_t, uint32_t>>, 2> bands_;
  UniformGrid::Bands band_order_;  // each band's slots in robot id order
  UniformGrid grid_;
  bool grid_valid_ = false;
  double dt_ = 0.2;  // config_.dt(), not divided out per move
  uint64_t tick_ = 0;
  uint64_t cumulative_ = 0;
  // block_penalties: FORDYCA's two penalty handlers, each robot's place in the order ARGoS visits them, the
  // robots penaltyStep visits, and the robots whose request the handlers took this step.
  BlockPenaltyHandler pickup_penalties_, drop_penalties_;
  std::vector<uint32_t> argos_rank_, penalty_visits_;
  std::vector<uint8_t> penalised_;
  uint64_t shadowed_lights_ = 0;
  std::vector<uint64_t> shadow_counts_;  // sense(): shadowed lights per chunk
  std::vector<uint8_t> shadow_masks_;    // by id
  // light_occlusion: by id and light, the robot whose body shadowed that light last tick, else kNoWitness. A
  // cache of lightShadowed's (it writes a robot's own entries only): it saves time, never changes a result.
  mutable std::vector<uint32_t> shadow_witness_;
  // light_occlusion: a bit per cell of grid_, set where a body is, so that a ray's stretch skips the empty
  // cells a word at a time.
  std::vector<uint64_t> shadow_bits_;
  double shadow_inv_cell_ = 1.0;  // 1 / grid_'s cell size
  // By slot: the robot traces its lights this tick (every robot, or with light_only_carrying the carriers).
  std::vector<uint8_t> traced_;
  static constexpr uint32_t kNoWitness = 0xffffffffu;
};

}  // namespace swarm_forage
