#pragma once
// The per-tick data exchanged between the world and the controllers, structure-of-arrays.
#include <cstdint>
#include <vector>

namespace swarm_forage {

enum Ground : uint8_t { kFloor = 0, kNest = 1, kBlockGround = 2, kCacheGround = 3 };
enum Event : uint8_t { kPickupDone = 1, kDropDone = 2, kBlockVanished = 4 };
enum Request : uint8_t { kNone = 0, kPickup = 1, kDrop = 2, kCachePickup = 3, kCacheDrop = 4 };

/// Every robot's readings for one tick; index = robot id. Floats, as on the wire.
struct SensorData {
  std::vector<float> x, y, theta;
  std::vector<uint8_t> threatened;
  std::vector<float> obstacle_x, obstacle_y;  // closest threatening obstacle, robot frame [m]
  std::vector<float> light_x, light_y;        // sum of unit vectors to the lights, robot frame
  std::vector<uint8_t> ground, events;
  std::vector<int32_t> carried_block;

  void resize(std::size_t n);
  std::size_t size() const { return x.size(); }
};

/// Wheel speeds and requests for a contiguous range of robots starting at first_id.
struct CommandData {
  uint32_t first_id = 0;
  std::vector<float> left, right;  // [m/s]
  std::vector<uint8_t> request;

  void resize(std::size_t n);
  std::size_t size() const { return left.size(); }
};

}  // namespace swarm_forage
