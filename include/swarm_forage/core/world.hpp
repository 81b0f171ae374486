#pragma once
// The simulated world: arena, nest, blocks and robots' bodies; motion, collisions, sensing,
// pick-up/drop execution and block respawn. Single-threaded and deterministic for one seed.
#include <cstdint>
#include <vector>

#include "swarm_forage/core/blocks.hpp"
#include "swarm_forage/core/config.hpp"
#include "swarm_forage/core/controller.hpp"
#include "swarm_forage/core/sensing.hpp"
#include "swarm_forage/core/spatial_grid.hpp"
#include "swarm_forage/core/static_cache.hpp"

namespace swarm_forage {

/// Robot bodies, structure-of-arrays.
struct RobotBodies {
  std::vector<double> x, y, theta;
  std::vector<int32_t> carried;         // block id, -1 when none
  std::vector<uint8_t> events;          // what was executed in the last step (Event flags)
  std::vector<uint8_t> last_request;    // the request of the last step ...
  std::vector<uint64_t> request_since;  // ... and the tick it was first made (serialised block operations)
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

  /// Sensor readings for the current tick.
  void sense(SensorData& out);

  /// Executes the requests, integrates motion for one tick and respawns delivered blocks.
  /// `commands` must cover every robot. `throttle` slows robots that carry a block: speed x (1 - V).
  /// `tasks` (GP-DPO) drives the static cache's re-creation.
  StepResult step(const CommandData& commands, double throttle, const TaskCounts& tasks = {});

  /// Test hook: puts robot i at (x, y) with heading theta (no overlap check).
  void setPose(uint32_t i, double x, double y, double theta);

  uint64_t tick() const { return tick_; }
  uint64_t delivered() const { return cumulative_; }
  uint32_t carrying() const;
  const WorldConfig& config() const { return config_; }
  const RobotBodies& robots() const { return robots_; }
  const BlockField& blocks() const { return blocks_; }
  const StaticCache& cache() const { return cache_; }
  bool overlapFree() const;  // no robot overlaps another robot or leaves the arena

 private:
  void placeRobots();
  void ensureGrid();
  /// With serialize_block_ops: the robots whose pick-up and nest drop may finish this tick (-1: none).
  std::pair<int32_t, int32_t> servedBlockOps(const CommandData& commands);
  /// kPickup or kDrop when robot i's request is a free-block pick-up or nest drop the world can execute
  /// now (what serialize_block_ops queues); kNone otherwise.
  uint8_t serializedOp(uint32_t i, uint8_t request) const;
  void move(uint32_t i, double left, double right);
  bool fits(uint32_t i, double x, double y) const;
  /// The robot overlapping most with robot i placed at (x, y); -1 when none.
  int32_t blocker(uint32_t i, double x, double y) const;
  uint8_t groundAt(double x, double y) const;
  void senseLineOfSight(SensorData& out);  // line_of_sight.cpp

  WorldConfig config_;
  RobotBodies robots_;
  BlockField blocks_;
  StaticCache cache_;
  std::vector<int32_t> scratch_;
  std::vector<Vec2> rays_, near_;  // proximity ray directions (robot frame); sense()'s neighbour offsets
  std::vector<uint8_t> pushed_;    // pushed by another robot this tick (at most once)
  UniformGrid grid_;
  bool grid_valid_ = false;
  uint64_t tick_ = 0;
  uint64_t cumulative_ = 0;
};

}  // namespace swarm_forage
