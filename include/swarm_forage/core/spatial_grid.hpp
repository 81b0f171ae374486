#pragma once
// Uniform-grid neighbour search over points (robot centres), rebuilt by a counting sort over the occupied
// cells only.
#include <cstdint>
#include <vector>

namespace swarm_forage {

class UniformGrid {
 public:
  UniformGrid() = default;
  UniformGrid(double width, double height, double cell_size);

  /// Indexes points 0..n-1 (cells hold contiguous index ranges); O(n), not O(cells).
  void build(const double* xs, const double* ys, std::size_t n);
  /// Adds one point to an index built incrementally (placement); call build() to compact.
  void insert(uint32_t index, double x, double y);
  void clear();

  /// Calls f(index) for every point in the 3x3 cells around (x, y): all points within cell_size.
  template <typename F>
  void forNeighbours(double x, double y, F&& f) const {
    const int cx = cellX(x), cy = cellY(y);
    for (int gy = cy - 1; gy <= cy + 1; ++gy) {
      if (gy < 0 || gy >= ny_) continue;
      for (int gx = cx - 1; gx <= cx + 1; ++gx) {
        if (gx < 0 || gx >= nx_) continue;
        const std::size_t c = static_cast<std::size_t>(gy) * nx_ + gx;
        for (uint32_t k = begin_[c]; k < end_[c]; ++k) f(sorted_[k]);
        for (uint32_t i = extra_head_[c]; i != kNone; i = extra_next_[i]) f(i);
      }
    }
  }

  double cellSize() const { return cell_; }

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  int cellX(double x) const;
  int cellY(double y) const;

  double cell_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<uint32_t> begin_, end_, touched_, sorted_, cell_of_;  // touched_: cells holding points
  std::vector<uint32_t> extra_head_, extra_next_, extra_touched_;   // incremental inserts as linked lists
};

}  // namespace swarm_forage
