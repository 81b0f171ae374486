#pragma once
// The per-tick data exchanged between the world and the controllers, structure-of-arrays.
#include <cmath>
#include <cstdint>
#include <vector>

#include "swarm_forage/core/util/geometry.hpp"

namespace swarm_forage {

enum Ground : uint8_t { kFloor = 0, kNest = 1, kBlockGround = 2, kCacheGround = 3 };
// kJoined: the robot was born into the swarm last tick (population dynamics): its controller starts afresh.
enum Event : uint8_t { kPickupDone = 1, kDropDone = 2, kBlockVanished = 4, kJoined = 8 };
enum Request : uint8_t { kNone = 0, kPickup = 1, kDrop = 2, kCachePickup = 3, kCacheDrop = 4 };

/// A robot's line of sight: the (2 radius + 1)^2 cells of `cell` metres around the cell it stands in
/// (1 m x 1 m by default). Blocks whose centre and caches whose centre lie in it are known exactly.
struct LineOfSight {
  double cell = 0.2;
  int radius = 2;
  Rect around(double x, double y) const { return view(std::floor(x / cell), std::floor(y / cell)); }
  /// The view from cell (cx, cy), whole numbers: around() of every point in it.
  Rect view(double cx, double cy) const {
    return {(cx - radius) * cell, (cy - radius) * cell, (cx + radius + 1) * cell, (cy + radius + 1) * cell};
  }
};

/// Every robot's readings for one tick; index = robot id. Floats, as on the wire.
struct SensorData {
  std::vector<float> x, y, theta;
  std::vector<uint8_t> threatened;
  std::vector<float> obstacle_x, obstacle_y;  // threatening obstacle (first proximity ray), robot frame [m]
  std::vector<float> light_x, light_y;        // sum of unit vectors to the lights, robot frame
  std::vector<uint8_t> ground, events;
  std::vector<int32_t> carried_block;
  // Population dynamics: 1 for an active robot, 0 for one dead or awaiting repair. EMPTY: every robot is
  // active (no population dynamics). An inactive robot's readings are its last pose and nothing else.
  std::vector<uint8_t> active;
  bool isActive(std::size_t i) const { return active.empty() || active[i] != 0; }

  // Line of sight, filled only for controllers that need it (DPO family); empty otherwise.
  // Robot i's blocks are entries [los_block_offset[i], los_block_offset[i + 1]) (size N + 1), in
  // increasing block id; the same for caches.
  std::vector<uint32_t> los_block_offset;
  std::vector<int32_t> los_block_id;
  std::vector<float> los_block_x, los_block_y;
  std::vector<uint32_t> los_cache_offset;
  std::vector<int32_t> los_cache_id;
  std::vector<float> los_cache_x, los_cache_y;
  std::vector<uint32_t> los_cache_blocks;  // blocks held by each cache seen

  void resize(std::size_t n);
  void clearLineOfSight();
  bool hasLineOfSight() const { return !los_block_offset.empty(); }
  std::size_t size() const { return x.size(); }
};

/// Wheel speeds and requests for a contiguous range of robots starting at first_id.
constexpr uint8_t kTaskNone = 3;  // GpTask::kNone

struct CommandData {
  uint32_t first_id = 0;
  std::vector<float> left, right;  // [m/s]
  std::vector<uint8_t> request;
  std::vector<uint8_t> task;  // GP-DPO's task of each robot (GpTask); kTaskNone for CRW and DPO: for display

  void resize(std::size_t n);
  std::size_t size() const { return left.size(); }
};

}  // namespace swarm_forage
