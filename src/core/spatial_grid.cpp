#include "swarm_forage/core/spatial_grid.hpp"

#include <algorithm>
#include <cmath>

namespace swarm_forage {

UniformGrid::UniformGrid(double width, double height, double cell_size)
    : cell_(cell_size),
      nx_(std::max(1, static_cast<int>(std::ceil(width / cell_size)))),
      ny_(std::max(1, static_cast<int>(std::ceil(height / cell_size)))) {
  clear();
}

int UniformGrid::cellX(double x) const { return std::clamp(static_cast<int>(x / cell_), 0, nx_ - 1); }
int UniformGrid::cellY(double y) const { return std::clamp(static_cast<int>(y / cell_), 0, ny_ - 1); }

void UniformGrid::clear() {
  const std::size_t cells = static_cast<std::size_t>(nx_) * ny_;
  begin_.assign(cells, 0);
  end_.assign(cells, 0);
  touched_.clear();
  sorted_.clear();
  extra_head_.assign(cells, kNone);
  extra_touched_.clear();
  extra_next_.clear();
}

// Only the cells that hold points are touched (and reset on the next build), so the cost of a build is
// O(points), whatever the arena's area. Within a cell, points stay in increasing index order.
void UniformGrid::build(const double* xs, const double* ys, std::size_t n) {
  for (uint32_t c : touched_) begin_[c] = end_[c] = 0;
  touched_.clear();
  for (uint32_t c : extra_touched_) extra_head_[c] = kNone;
  extra_touched_.clear();
  extra_next_.clear();
  cell_of_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<uint32_t>(cellY(ys[i]) * nx_ + cellX(xs[i]));
    cell_of_[i] = c;
    if (end_[c]++ == 0) touched_.push_back(c);  // end_ counts until the offsets are laid out
  }
  uint32_t offset = 0;
  for (uint32_t c : touched_) {
    const uint32_t count = end_[c];
    begin_[c] = end_[c] = offset;
    offset += count;
  }
  sorted_.resize(n);
  for (std::size_t i = 0; i < n; ++i) sorted_[end_[cell_of_[i]]++] = static_cast<uint32_t>(i);
}

void UniformGrid::insert(uint32_t index, double x, double y) {
  if (extra_next_.size() <= index) extra_next_.resize(index + 1, kNone);
  const std::size_t c = static_cast<std::size_t>(cellY(y)) * nx_ + cellX(x);
  if (extra_head_[c] == kNone) extra_touched_.push_back(static_cast<uint32_t>(c));
  extra_next_[index] = extra_head_[c];
  extra_head_[c] = index;
}

}  // namespace swarm_forage
