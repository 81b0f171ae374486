#pragma once
// Uniform-grid neighbour search over points (robot centres). build() sorts the points by cell, row-major,
// so that a row of neighbouring cells is one contiguous range of sorted positions: callers keep their
// per-point data in sorted order and scan it without indirection.
#include <algorithm>
#include <cstdint>
#include <vector>

namespace swarm_forage {

class UniformGrid {
 public:
  UniformGrid() = default;
  UniformGrid(double width, double height, double cell_size);

  /// Bands of `rows` grid rows, each a contiguous range of sorted positions (rows are row-major): their
  /// positions in point index order. Band b's are order[start[b], start[b + 1]).
  struct Bands {
    int rows = 1;
    std::vector<uint32_t> start, order;
  };
  /// Sorts points 0..n-1 by cell (increasing index within a cell). O(n): a grid of more than a few cells
  /// per point is handled through its occupied cells only, so the cost does not grow with the area.
  /// With `present`, the points it marks 0 are in no cell (no query finds them): they take the last
  /// sorted positions, in index order, and cellOf() gives them kNowhere.
  /// With `bands`, also fills its start and order for its rows.
  void build(const double* xs, const double* ys, std::size_t n, const uint8_t* present = nullptr,
             Bands* bands = nullptr);
  /// Adds one point to an index built incrementally (placement); reported by index, not sorted position.
  void insert(uint32_t index, double x, double y);
  void clear();
  /// The bytes of the per-cell arrays of a grid over width x height (clear() allocates them, build() may
  /// add a bit per cell): what an arena costs whatever its swarm.
  static double bytesFor(double width, double height, double cell_size);

  /// The point at each sorted position, and each point's cell (row-major).
  const std::vector<uint32_t>& order() const { return sorted_; }
  const std::vector<uint32_t>& rank() const { return rank_; }  // the sorted position of each point
  uint32_t cellOf(uint32_t index) const { return cell_of_[index]; }
  /// The points in cells (all but those `present` left out): sorted positions [0, placed()).
  uint32_t placed() const { return placed_; }
  static constexpr uint32_t kNowhere = 0xffffffffu;

  /// Calls f(k) for every point in the 3x3 cells around (x, y), all points within cell_size: k is a sorted
  /// position after build(), an index for points added with insert().
  template <typename F>
  void forNeighbours(double x, double y, F&& f) const {
    const int cx = cellX(x), cy = cellY(y);
    const int x0 = std::max(cx - 1, 0), x1 = std::min(cx + 1, nx_ - 1);
    for (int gy = std::max(cy - 1, 0); gy <= std::min(cy + 1, ny_ - 1); ++gy) {
      const std::size_t row = static_cast<std::size_t>(gy) * nx_;
      if (dense_) {  // every cell is laid out: the row's cells are one range
        for (uint32_t k = start_[row + x0], e = start_[row + x1 + 1]; k < e; ++k) f(k);
      } else {
        for (int gx = x0; gx <= x1; ++gx)
          for (uint32_t k = range_[row + gx].begin, e = range_[row + gx].end; k < e; ++k) f(k);
      }
      if (has_extra_)
        for (int gx = x0; gx <= x1; ++gx)
          for (uint32_t i = extra_head_[row + gx]; i != kNone; i = extra_next_[i]) f(i);
    }
  }

  /// forNeighbours by runs of sorted positions, for a grid that build() left without insert()s: the runs
  /// [begin, end) around cell (cx, cy) = (cellX(x), cellY(y)) into out, in forNeighbours' order; how many
  /// (one per row when every cell is laid out, else one per cell: at most kMaxRuns).
  struct Run {
    uint32_t begin, end;
  };
  static constexpr std::size_t kMaxRuns = 9;
  std::size_t neighbourRuns(int cx, int cy, Run* out) const {
    const int x0 = std::max(cx - 1, 0), x1 = std::min(cx + 1, nx_ - 1);
    const int y0 = std::max(cy - 1, 0), y1 = std::min(cy + 1, ny_ - 1);
    const std::size_t first_row = static_cast<std::size_t>(y0) * nx_;
    std::size_t n = 0;
    if (dense_) {
      const uint32_t* start = start_.data() + first_row;
      for (int gy = y0; gy <= y1; ++gy, start += nx_) out[n++] = Run{start[x0], start[x1 + 1]};
      return n;
    }
    const Range* row = range_.data() + first_row;
    for (int gy = y0; gy <= y1; ++gy, row += nx_)
      for (int gx = x0; gx <= x1; ++gx) out[n++] = Run{row[gx].begin, row[gx].end};
    return n;
  }

  /// The sorted positions [begin, end) of cell c (row-major) after build(), for a grid without insert()s.
  Run cellRun(std::size_t c) const {
    return dense_ ? Run{start_[c], start_[c + 1]} : Run{range_[c].begin, range_[c].end};
  }

  /// Calls f(k) for every point in the cells gx0..gx1 of row gy (all in range).
  template <typename F>
  void forRow(int gy, int gx0, int gx1, F&& f) const {
    const std::size_t row = static_cast<std::size_t>(gy) * nx_;
    if (dense_) {
      for (uint32_t k = start_[row + gx0], e = start_[row + gx1 + 1]; k < e; ++k) f(k);
    } else {
      for (int gx = gx0; gx <= gx1; ++gx)
        for (uint32_t k = range_[row + gx].begin, e = range_[row + gx].end; k < e; ++k) f(k);
    }
    if (has_extra_)
      for (int gx = gx0; gx <= gx1; ++gx)
        for (uint32_t i = extra_head_[row + gx]; i != kNone; i = extra_next_[i]) f(i);
  }

  double cellSize() const { return cell_; }
  int columns() const { return nx_; }
  int rows() const { return ny_; }
  int cellX(double x) const { return std::clamp(static_cast<int>(x / cell_), 0, nx_ - 1); }
  int cellY(double y) const { return std::clamp(static_cast<int>(y / cell_), 0, ny_ - 1); }

 private:
  static constexpr uint32_t kNone = 0xffffffffu;

  double cell_ = 1.0;
  int nx_ = 0, ny_ = 0;
  struct Range {
    uint32_t begin, end;
  };
  std::vector<Range> range_;     // per cell: its sorted positions (a sparse layout)
  std::vector<uint32_t> start_;  // per cell and one more: the first sorted position (a dense layout)
  std::vector<uint32_t> count_;  // per cell: its points while build() counts them, else 0
  bool dense_ = false;           // start_ laid out for every cell (else: range_ for touched_ only)
  std::vector<uint32_t> touched_, sorted_, rank_, cell_of_;        // touched_: cells holding points
  std::vector<uint32_t> extra_head_, extra_next_, extra_touched_;  // incremental inserts as linked lists
  bool has_extra_ = false;
  std::vector<uint32_t> band_next_;  // build(): each band's next position in Bands::order
  std::vector<uint64_t> bits_;       // build(): the occupied cells, one bit each (all zero between builds)
  uint32_t placed_ = 0;
};

}  // namespace swarm_forage
