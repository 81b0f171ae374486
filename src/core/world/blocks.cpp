#include "swarm_forage/core/world/blocks.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "swarm_forage/core/util/rng.hpp"

namespace swarm_forage {

void BlockField::init(const ArenaConfig& arena, uint32_t seed) {
  arena_ = arena;
  seed_ = seed;
  draws_ = 0;
  ++version_;
  const std::size_t n = arena.n_blocks;
  x_.assign(n, 0);
  y_.assign(n, 0);
  carrier_.assign(n, -1);
  kind_.resize(n);
  for (std::size_t b = 0; b < n; ++b) kind_[b] = b % 2 == 0 ? kCube : kRamp;
  nx_ = static_cast<int>(std::ceil(arena.width / kCell));
  ny_ = static_cast<int>(std::ceil(arena.height / kCell));
  cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  occupied_.assign(cells_.size(), 0);
  clearNear();
  for (std::size_t b = 0; b < n; ++b) placeInSource(static_cast<int32_t>(b));
}

bool BlockField::gridSpan(const Rect& r, int& x0, int& x1, int& y0, int& y1) const {
  x0 = std::max(0, static_cast<int>(r.min_x / kCell));
  x1 = std::min(nx_ - 1, static_cast<int>(r.max_x / kCell));
  y0 = std::max(0, static_cast<int>(r.min_y / kCell));
  y1 = std::min(ny_ - 1, static_cast<int>(r.max_y / kCell));
  return x0 <= x1 && y0 <= y1;
}

bool BlockField::centreCell(int32_t b, int& cx, int& cy) const {
  // The footprint holds the centre, so link() put the block in this cell's list.
  cx = static_cast<int>(x_[b] / kCell);
  cy = static_cast<int>(y_[b] / kCell);
  return cx >= 0 && cx < nx_ && cy >= 0 && cy < ny_;
}

template <typename F>
void BlockField::forCells(const Rect& r, F&& f) {
  int x0, x1, y0, y1;
  if (!gridSpan(r, x0, x1, y0, y1)) return;
  for (int cy = y0; cy <= y1; ++cy)
    for (int cx = x0; cx <= x1; ++cx) f(static_cast<std::size_t>(cy) * nx_ + cx);
}

void BlockField::link(int32_t b) {
  forCells(footprint(b), [&](std::size_t c) {
    cells_[c].push_back(b);
    occupied_[c] = 1;
  });
  markNear(b);
  ++version_;
}

void BlockField::unlink(int32_t b) {
  forCells(footprint(b), [&](std::size_t c) {
    cells_[c].erase(std::remove(cells_[c].begin(), cells_[c].end(), b), cells_[c].end());
    occupied_[c] = cells_[c].empty() ? 0 : 1;
  });
  unmarkNear(b);
  ++version_;
}

bool BlockField::nearSquares(int32_t b, int& x0, int& x1, int& y0, int& y1) const {
  // The squares a point within kNearReach of the footprint can lie in (the margin covers the roundings).
  const Rect f = footprint(b);
  const double reach = kNearReach + 1e-9;
  x0 = std::max(0, static_cast<int>((f.min_x - reach) / kNearCell));
  x1 = std::min(near_nx_ - 1, static_cast<int>((f.max_x + reach) / kNearCell));
  y0 = std::max(0, static_cast<int>((f.min_y - reach) / kNearCell));
  y1 = std::min(near_ny_ - 1, static_cast<int>((f.max_y + reach) / kNearCell));
  return x0 <= x1 && y0 <= y1;
}

void BlockField::markNear(int32_t b) {
  int x0, x1, y0, y1;
  if (!nearSquares(b, x0, x1, y0, y1)) return;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const std::size_t c = static_cast<std::size_t>(y) * near_nx_ + x;
      near_bits_[c / 64] |= uint64_t{1} << (c % 64);
    }
}

void BlockField::unmarkNear(int32_t b) {
  int x0, x1, y0, y1;
  if (!nearSquares(b, x0, x1, y0, y1)) return;
  const double reach = kNearReach + 1e-6;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      // Another free block near this square meets it widened by the reach, so it is linked in a look-up
      // cell that the widened square touches: the bit stays if one of those has the square in its range.
      bool near = false;
      const Rect wide{x * kNearCell - reach, y * kNearCell - reach, (x + 1) * kNearCell + reach,
                      (y + 1) * kNearCell + reach};
      forCells(wide, [&](std::size_t c) {
        for (const int32_t o : cells_[c]) {
          int ox0, ox1, oy0, oy1;
          if (!near && nearSquares(o, ox0, ox1, oy0, oy1))
            near = ox0 <= x && x <= ox1 && oy0 <= y && y <= oy1;
        }
      });
      const std::size_t c = static_cast<std::size_t>(y) * near_nx_ + x;
      const uint64_t bit = uint64_t{1} << (c % 64);
      near_bits_[c / 64] = near ? near_bits_[c / 64] | bit : near_bits_[c / 64] & ~bit;
    }
}

void BlockField::clearNear() {
  near_nx_ = static_cast<int>(std::ceil(arena_.width / kNearCell));
  near_ny_ = static_cast<int>(std::ceil(arena_.height / kNearCell));
  near_w_ = near_nx_ * kNearCell;
  near_h_ = near_ny_ * kNearCell;
  const std::size_t squares = static_cast<std::size_t>(near_nx_) * near_ny_;
  near_bits_.assign(squares / 64 + 1, 0);
}

void BlockField::layOutNear() {
  clearNear();
  for (std::size_t b = 0; b < carrier_.size(); ++b)
    if (carrier_[b] == kFree) markNear(static_cast<int32_t>(b));
}

int32_t BlockField::blockIn(std::size_t c, double x, double y) const {
  for (int32_t b : cells_[c])
    if (footprint(b).contains(x, y)) return b;
  return -1;
}

void BlockField::pickUp(int32_t block, int32_t robot) {
  unlink(block);
  carrier_[block] = robot;
}

void BlockField::putDown(int32_t block, double x, double y) {
  carrier_[block] = -1;
  x_[block] = x;
  y_[block] = y;
  link(block);
}

void BlockField::stash(int32_t block, double x, double y) {
  if (carrier_[block] == kFree) unlink(block);
  carrier_[block] = kInCache;
  x_[block] = x;
  y_[block] = y;
  ++version_;
}

void BlockField::respawn(int32_t block) {
  carrier_[block] = -1;
  placeInSource(block);
}

void BlockField::placeInSource(int32_t b) {
  const Rect src = arena_.source();
  const double hx = sizeX(b) / 2, hy = sizeY(b) / 2;
  // Rejection sampling; validation keeps the source at most a quarter full, so this ends quickly.
  for (int attempt = 0; attempt < 100000; ++attempt) {
    CounterRng rng(seed_, RngStream::kBlocks, 0, draws_++);
    const double x = rng.uniform(src.min_x + hx, src.max_x - hx);
    const double y = rng.uniform(src.min_y + hy, src.max_y - hy);
    const Rect r = Rect::centered(x, y, 2 * hx, 2 * hy);
    bool free = true;
    forCells(r, [&](std::size_t c) {
      for (int32_t o : cells_[c])
        if (o != b && footprint(o).overlaps(r)) free = false;
    });
    if (!free) continue;
    x_[b] = x;
    y_[b] = y;
    link(b);
    return;
  }
  throw std::runtime_error("no free place left in the block source");
}

}  // namespace swarm_forage
