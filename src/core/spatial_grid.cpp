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
  start_.assign(cells + 1, 0);
  sorted_.clear();
  extra_head_.assign(cells, kNone);
  extra_next_.clear();
}

void UniformGrid::build(const double* xs, const double* ys, std::size_t n) {
  const std::size_t cells = static_cast<std::size_t>(nx_) * ny_;
  start_.assign(cells + 1, 0);
  cell_of_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    cell_of_[i] = static_cast<uint32_t>(cellY(ys[i]) * nx_ + cellX(xs[i]));
    ++start_[cell_of_[i] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  sorted_.resize(n);
  std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) sorted_[fill[cell_of_[i]]++] = static_cast<uint32_t>(i);
  extra_head_.assign(cells, kNone);
  extra_next_.clear();
}

void UniformGrid::insert(uint32_t index, double x, double y) {
  if (extra_next_.size() <= index) extra_next_.resize(index + 1, kNone);
  const std::size_t c = static_cast<std::size_t>(cellY(y)) * nx_ + cellX(x);
  extra_next_[index] = extra_head_[c];
  extra_head_[c] = index;
}

}  // namespace swarm_forage
