#include "swarm_forage/core/world/spatial_grid.hpp"

#include <algorithm>
#include <cmath>

namespace swarm_forage {

UniformGrid::UniformGrid(double width, double height, double cell_size)
    : cell_(cell_size),
      nx_(std::max(1, static_cast<int>(std::ceil(width / cell_size)))),
      ny_(std::max(1, static_cast<int>(std::ceil(height / cell_size)))) {
  clear();
}

void UniformGrid::clear() {
  const std::size_t cells = static_cast<std::size_t>(nx_) * ny_;
  range_.assign(cells, Range{0, 0});
  dense_ = false;
  touched_.clear();
  sorted_.clear();
  placed_ = 0;
  extra_head_.assign(cells, kNone);
  extra_touched_.clear();
  extra_next_.clear();
  has_extra_ = false;
}

// A counting sort by cell. With at most 16 cells per point, every cell is laid out (O(cells) = O(n));
// otherwise only the occupied cells are, in row-major order from a bitmap of the cells (O(cells / 64) =
// O(n)), or sorted when even the bitmap is far larger than the points: the cost follows the points, not
// the arena's area. Every path gives the same order (measured: issue 25, docs/performance.md).
void UniformGrid::build(const double* xs, const double* ys, std::size_t n, const uint8_t* present) {
  const std::size_t cells = range_.size();
  if (dense_)
    std::fill(range_.begin(), range_.end(), Range{0, 0});
  else
    for (uint32_t c : touched_) range_[c] = Range{0, 0};
  touched_.clear();
  for (uint32_t c : extra_touched_) extra_head_[c] = kNone;
  extra_touched_.clear();
  extra_next_.clear();
  has_extra_ = false;
  dense_ = cells <= 16 * n + 64;
  cell_of_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (present && !present[i]) {
      cell_of_[i] = kNowhere;
      continue;
    }
    const auto c = static_cast<uint32_t>(cellY(ys[i]) * nx_ + cellX(xs[i]));
    cell_of_[i] = c;
    if (range_[c].end++ == 0 && !dense_) touched_.push_back(c);  // end counts until laid out
  }
  uint32_t offset = 0;
  const auto layOut = [&](uint32_t c) {
    const uint32_t count = range_[c].end;
    range_[c] = Range{offset, offset};
    offset += count;
  };
  if (dense_) {
    for (std::size_t c = 0; c < cells; ++c) layOut(static_cast<uint32_t>(c));
  } else if (cells / 64 <= 16 * n + 64) {  // a bit per cell: row-major order by a scan of the words
    bits_.resize(cells / 64 + 1);
    for (uint32_t c : touched_) bits_[c / 64] |= uint64_t{1} << (c % 64);
    for (std::size_t w = 0; w < bits_.size(); ++w) {
      for (uint64_t b = bits_[w]; b; b &= b - 1) layOut(static_cast<uint32_t>(w * 64 + __builtin_ctzll(b)));
      bits_[w] = 0;
    }
  } else {
    std::sort(touched_.begin(), touched_.end());
    for (uint32_t c : touched_) layOut(c);
  }
  placed_ = offset;
  sorted_.resize(n);
  rank_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t k = cell_of_[i] == kNowhere ? offset++ : range_[cell_of_[i]].end++;
    sorted_[k] = static_cast<uint32_t>(i);
    rank_[i] = k;
  }
}

void UniformGrid::insert(uint32_t index, double x, double y) {
  if (extra_next_.size() <= index) extra_next_.resize(index + 1, kNone);
  const std::size_t c = static_cast<std::size_t>(cellY(y)) * nx_ + cellX(x);
  if (extra_head_[c] == kNone) extra_touched_.push_back(static_cast<uint32_t>(c));
  has_extra_ = true;
  extra_next_[index] = extra_head_[c];
  extra_head_[c] = index;
}

}  // namespace swarm_forage
