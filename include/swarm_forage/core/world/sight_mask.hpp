#pragma once
// Which line-of-sight cells may see something: one bit per LineOfSight cell, set around every free
// block's centre and around the cache, rebuilt each tick before the robots look. Most robots stand
// where they see nothing; a clear bit lets them skip the exact query (World::gatherSight).
#include <cstdint>
#include <vector>

#include "swarm_forage/core/world/blocks.hpp"
#include "swarm_forage/core/world/sensing.hpp"
#include "swarm_forage/core/world/static_cache.hpp"

namespace swarm_forage {

class SightMask {
 public:
  void build(const LineOfSight& los, const ArenaConfig& arena, const BlockField& blocks,
             const StaticCache& cache);
  /// False only if a robot at (x, y) can see no free block and no cache.
  bool maySee(double x, double y) const {
    const double fx = x * inv_cell_, fy = y * inv_cell_;
    if (!(fx >= 0 && fx < nx_ && fy >= 0 && fy < ny_)) return true;  // off the table: ask
    const auto cx = static_cast<uint32_t>(fx), cy = static_cast<uint32_t>(fy);
    return (bits_[cy * words_ + (cx >> 6)] >> (cx & 63)) & 1;
  }

 private:
  /// Sets the bits of the cells whose view may overlap the rectangle (a point for a block).
  void mark(double min_x, double min_y, double max_x, double max_y);

  double inv_cell_ = 0, nx_ = 0, ny_ = 0;  // 0 columns: every robot asks
  int margin_ = 0;                         // cells, each side
  std::size_t words_ = 0;                  // per row
  std::vector<uint64_t> bits_;
};

}  // namespace swarm_forage
