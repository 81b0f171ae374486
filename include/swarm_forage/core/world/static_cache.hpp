#pragma once
// The GP-DPO static cache (docs/design-model.md, Model): a square between nest and source holding blocks;
// it vanishes when a pick-up leaves too few and is re-created at random, faster when there are
// many harvesters per collector.
#include <cstdint>
#include <vector>

#include "swarm_forage/core/world/blocks.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

class StateArchive;

class StaticCache {
 public:
  void init(const ArenaConfig& arena, const CacheConfig& config);
  bool exists() const { return exists_; }
  const Rect& area() const { return area_; }
  Vec2 center() const { return {(area_.min_x + area_.max_x) / 2, (area_.min_y + area_.max_y) / 2}; }
  std::size_t size() const { return blocks_.size(); }
  bool contains(double x, double y) const { return exists_ && area_.contains(x, y); }

  /// Fills the cache with the lowest-id free blocks; false when too few are free.
  bool create(BlockField& field);
  /// A block for `robot`, or -1; removes the cache (its last blocks go to the floor) when too few remain.
  int32_t take(BlockField& field, int32_t robot);
  /// Adds a carried block to the cache.
  void put(BlockField& field, int32_t block);
  /// Probability of re-creation in one tick with `harvesters` and `collectors`.
  double recreationProbability(uint32_t harvesters, uint32_t collectors) const;
  void persist(StateArchive& a);  // world_checkpoint.cpp

 private:
  CacheConfig config_;
  uint32_t capacity_ = 0;
  Rect area_{0, 0, 0, 0};
  bool exists_ = false;
  std::vector<int32_t> blocks_;
};

}  // namespace swarm_forage
