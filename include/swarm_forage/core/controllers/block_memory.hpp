#pragma once
// The DPO store of objects seen in line of sight (docs/design-model.md, Controllers): per robot, the blocks
// (or caches) it has seen, each with its last known position and a pheromone density rho that is set when the
// object is first seen or seen at a new place and decays every tick. An object whose remembered
// position is certainly in sight but is not reported any more is forgotten.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "swarm_forage/core/util/geometry.hpp"
#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

class StateArchive;

struct Remembered {
  int32_t id;
  float x, y;
  double rho;  // pheromone density
};

/// The pheromone model of one kind of object.
struct PheromoneModel {
  double initial = 1.0;              // rho when first seen or seen at a new place
  double decay = 1e-5;               // rho <- (1 - decay) rho every tick
  double new_place_distance = 0.01;  // m; seen farther than this from where remembered = a new place
};

/// The part of the line-of-sight rectangle of a robot at (x, y) that is in sight for every pose within
/// `margin` of it, shrunk by `margin`: a remembered object there that is not reported is certainly gone,
/// even when float rounding of poses on the wire puts the robot in a neighbouring cell.
Rect certainSight(const LineOfSight& los, double x, double y, double margin = 1e-3);

/// U = (|object - nest| / |object - robot|) exp(rho) (docs/design-model.md, Controllers; the robot distance
/// is floored at 1e-9 m so an object under the robot has a finite, largest utility).
double objectUtility(const Vec2& object, const Vec2& robot, const Vec2& nest, double rho);

/// Index of the entry of highest utility among those farther than `exclude` from the robot (the first
/// such, i.e. the lowest id, on ties); -1 when there is none.
int bestByUtility(const std::vector<Remembered>& entries, const Vec2& robot, const Vec2& nest,
                  double exclude);

/// One robot range's stores, one flat vector per robot kept sorted by id. A robot remembers each id at
/// most once, so its store never holds more entries than there are distinct objects.
class ObjectMemory {
 public:
  explicit ObjectMemory(std::size_t robots = 0) : entries_(robots) {}

  std::size_t robots() const { return entries_.size(); }
  const std::vector<Remembered>& of(uint32_t local) const { return entries_[local]; }
  std::size_t size(uint32_t local) const { return entries_[local].size(); }
  const Remembered* find(uint32_t local, int32_t id) const;
  /// Forgets `id` (a no-op for an unknown id or -1); true when it was remembered.
  bool forget(uint32_t local, int32_t id);
  void clear(uint32_t local) { entries_[local].clear(); }
  /// Asks for robot `local`'s store (if any) to be loaded: each store is a heap block of its own, which the
  /// hardware's prefetcher cannot guess.
  void prefetch(uint32_t local) const {
    if (local < entries_.size()) __builtin_prefetch(entries_[local].data());
  }
  /// Saves or loads robot `local`'s store (controller_checkpoint.cpp).
  void persist(StateArchive& a, uint32_t local);

  /// One tick of robot `local`: every rho decays once, then the objects reported in sight
  /// (ids[k], xs[k], ys[k]) for k < n, in increasing id, are recorded, and remembered objects lying in
  /// `sight` that were not reported are forgotten. Reports of `skip` (e.g. the carried block) are ignored.
  void update(uint32_t local, const PheromoneModel& model, const Rect& sight, const int32_t* ids,
              const float* xs, const float* ys, uint32_t n, int32_t skip);

 private:
  std::vector<std::vector<Remembered>> entries_;
  std::vector<Remembered> scratch_;  // merge buffer reused across robots and ticks
};

/// Robot i's slice [begin, end) of a flattened line-of-sight list; empty when the offsets are absent.
inline void lineOfSightSlice(const std::vector<uint32_t>& offset, uint32_t i, uint32_t& begin,
                             uint32_t& end) {
  if (offset.size() > static_cast<std::size_t>(i) + 1) {
    begin = offset[i];
    end = offset[i + 1];
  } else {
    begin = end = 0;
  }
}

}  // namespace swarm_forage
