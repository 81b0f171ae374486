#pragma once
// This tick's line-of-sight index (World::gatherSight), rebuilt before the robots look: a bit per
// LineOfSight cell, set where the view from that cell or a neighbour holds a free block or overlaps the
// cache (most robots see nothing and skip the query), and the free blocks by row of the block grid, each
// row by x, for the query.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "swarm_forage/core/world/blocks.hpp"
#include "swarm_forage/core/world/sensing.hpp"
#include "swarm_forage/core/world/static_cache.hpp"

namespace swarm_forage {

class SightIndex {
 public:
  void build(const LineOfSight& los, const ArenaConfig& arena, const BlockField& blocks,
             const StaticCache& cache);
  /// The bytes of the mask build() allocates over `arena` (at most 2 MiB).
  static double maskBytes(const LineOfSight& los, const ArenaConfig& arena);
  /// False only if a robot at (x, y) sees no free block and no cache.
  bool maySee(double x, double y) const {
    const double fx = x * inv_cell_, fy = y * inv_cell_;
    if (!(fx >= 0 && fx < nx_ && fy >= 0 && fy < ny_)) return true;  // off the mask: ask
    const auto cx = static_cast<uint32_t>(fx), cy = static_cast<uint32_t>(fy);
    return (bits_[cy * words_ + (cx >> 6)] >> (cx & 63)) & 1;
  }
  /// Calls f(block) once for every free block whose centre lies in `view`, in increasing block id:
  /// those BlockField counts in the grid cell holding their centre (BlockField::centreCell).
  template <typename F>
  void forFreeBlocksIn(const Rect& view, std::vector<int32_t>& scratch, F&& f) const;

 private:
  /// The cells k on one axis whose view [lo(k), hi(k)] holds the point v = w (open: overlaps the open
  /// interval (v, w)), and one more each side; false when none.
  bool span(double v, double w, bool open, int& first, int& last) const;
  /// Sets the bits of the cells [x0, x1] x [y0, y1] that are on the mask.
  void mark(int x0, int x1, int y0, int y1);

  // The mask.
  LineOfSight los_;
  double inv_cell_ = 1, nx_ = 0, ny_ = 0;  // 0 columns: every robot asks
  std::size_t words_ = 0;                  // per row
  std::vector<uint64_t> bits_;
  // The free blocks: spots_[row_start_[r], row_start_[r + 1]) lie in grid row r, by x.
  struct Spot {
    double x, y;
    int32_t id;
  };
  const BlockField* blocks_ = nullptr;
  std::vector<uint32_t> row_start_, cursor_;
  std::vector<Spot> spots_, found_, next_;  // found_: in id order; next_: this tick's, to compare
  std::vector<int> found_row_, next_row_;
  // What else the index was built from: kept while it and the free blocks stay as they were.
  struct Key {
    double cell;
    int radius;
    double width, height;
    int rows;
    bool cache;
    Rect area;
    bool operator==(const Key& o) const {
      return cell == o.cell && radius == o.radius && width == o.width && height == o.height &&
             rows == o.rows && cache == o.cache && area.min_x == o.area.min_x && area.min_y == o.area.min_y &&
             area.max_x == o.area.max_x && area.max_y == o.area.max_y;
    }
  };
  Key key_{};
  bool built_ = false;
};

template <typename F>
void SightIndex::forFreeBlocksIn(const Rect& view, std::vector<int32_t>& scratch, F&& f) const {
  scratch.clear();
  int x0, x1, y0, y1;
  if (!blocks_->gridSpan(view, x0, x1, y0, y1)) return;
  for (int r = y0; r <= y1; ++r) {
    const Spot *s = spots_.data() + row_start_[r], *const end = spots_.data() + row_start_[r + 1];
    s = std::lower_bound(s, end, view.min_x, [](const Spot& a, double v) { return a.x < v; });
    for (; s != end && s->x <= view.max_x; ++s)
      if (view.contains(s->x, s->y)) scratch.push_back(s->id);  // then its cell is in [x0, x1] too
  }
  if (scratch.size() > 1) std::sort(scratch.begin(), scratch.end());  // mostly none: no call
  for (int32_t b : scratch) f(b);
}

}  // namespace swarm_forage
