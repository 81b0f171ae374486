// Line of sight for the DPO family: the blocks and caches whose centre lies in each robot's view. Each
// chunk of robots gathers its own lists (in parallel with sensing), then copies them into its place in
// the joined lists, robot order.
#include <algorithm>
#include <cmath>

#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

namespace {
/// The mask's columns and rows over `arena`; false when it has more than 2^24 cells (too fine a grid to be
/// worth it: every robot asks).
bool maskSize(const LineOfSight& los, const ArenaConfig& arena, double& nx, double& ny) {
  const double inv_cell = 1.0 / los.cell;
  nx = std::floor(arena.width * inv_cell) + 2;
  ny = std::floor(arena.height * inv_cell) + 2;
  return nx * ny <= double(1 << 24);
}
}  // namespace

double SightIndex::maskBytes(const LineOfSight& los, const ArenaConfig& arena) {
  double nx, ny;
  return maskSize(los, arena, nx, ny) ? std::ceil(nx / 64) * ny * sizeof(uint64_t) : 0.0;
}

void SightIndex::build(const LineOfSight& los, const ArenaConfig& arena, const BlockField& blocks,
                       const StaticCache& cache) {
  blocks_ = &blocks;
  // The free blocks a query may report (on the grid), in id order, with their grid row.
  next_.clear();
  next_row_.clear();
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const auto id = static_cast<int32_t>(b);
    int cx, cy;
    if (blocks.carrier(id) != kFree || !blocks.centreCell(id, cx, cy)) continue;
    next_.push_back({blocks.x(id), blocks.y(id), id});
    next_row_.push_back(cy);
  }
  // The index is a function of these alone: when none changed since the last build (most ticks of a small
  // swarm: no block picked up or dropped), it is kept, as rebuilding would make it bit for bit again.
  const Key key{los.cell,
                los.radius,
                arena.width,
                arena.height,
                blocks.gridRows(),
                cache.exists(),
                cache.exists() ? cache.area() : Rect{}};
  if (built_ && key == key_ && next_row_ == found_row_ &&
      std::equal(next_.begin(), next_.end(), found_.begin(), found_.end(),
                 [](const Spot& a, const Spot& b) { return a.x == b.x && a.y == b.y && a.id == b.id; }))
    return;
  built_ = true;
  key_ = key;
  found_.swap(next_);
  found_row_.swap(next_row_);
  // By row (counting sort), each row by x.
  row_start_.assign(static_cast<std::size_t>(blocks.gridRows()) + 1, 0);
  for (int r : found_row_) ++row_start_[static_cast<std::size_t>(r) + 1];
  for (std::size_t r = 1; r < row_start_.size(); ++r) row_start_[r] += row_start_[r - 1];
  cursor_.assign(row_start_.begin(), row_start_.end() - 1);
  spots_.resize(found_.size());
  for (std::size_t k = 0; k < found_.size(); ++k)
    spots_[cursor_[static_cast<std::size_t>(found_row_[k])]++] = found_[k];
  for (std::size_t r = 0; r + 1 < row_start_.size(); ++r)
    std::sort(spots_.begin() + row_start_[r], spots_.begin() + row_start_[r + 1],
              [](const Spot& a, const Spot& b) { return a.x < b.x || (a.x == b.x && a.id < b.id); });
  // The mask: a bit is set where the view from the cell or a neighbour holds a block's centre or overlaps
  // the cache. A robot's cell there is x * inv_cell_, not around()'s x / cell: they may round apart,
  // by one cell.
  los_ = los;
  inv_cell_ = 1.0 / los.cell;
  double nx, ny;
  if (!maskSize(los, arena, nx, ny)) {
    nx_ = ny_ = 0;
    return;
  }
  nx_ = nx;
  ny_ = ny;
  words_ = (static_cast<std::size_t>(nx) + 63) / 64;
  bits_.assign(words_ * static_cast<std::size_t>(ny), 0);
  int x0, x1, y0, y1;
  for (const Spot& s : found_)
    if (span(s.x, s.x, false, x0, x1) && span(s.y, s.y, false, y0, y1)) mark(x0, x1, y0, y1);
  const Rect& a = cache.area();
  if (cache.exists() && span(a.min_x, a.max_x, true, x0, x1) && span(a.min_y, a.max_y, true, y0, y1))
    mark(x0, x1, y0, y1);
}

bool SightIndex::span(double v, double w, bool open, int& first, int& last) const {
  // view() on one axis: lo(k) = (k - radius) cell, hi(k) = (k + radius + 1) cell, both rising with k.
  // Start outside the answer and step in.
  const auto lo = [&](double k) { return los_.view(k, k).min_x; };
  const auto hi = [&](double k) { return los_.view(k, k).max_x; };
  double a = std::floor(v / los_.cell) - los_.radius - 2, b = std::floor(w / los_.cell) + los_.radius + 2;
  for (int step = 0; step < 8 && (open ? !(hi(a) > v) : !(hi(a) >= v)); ++step) ++a;
  for (int step = 0; step < 8 && (open ? !(lo(b) < w) : !(lo(b) <= w)); ++step) --b;
  // Clamped as doubles (a far coordinate never reaches an integer conversion); mark() clamps to the mask.
  first = static_cast<int>(std::clamp(a - 1, -1.0, 1e9));
  last = static_cast<int>(std::clamp(b + 1, -1.0, 1e9));
  return a <= b;
}

void SightIndex::mark(int x0, int x1, int y0, int y1) {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, static_cast<int>(nx_) - 1);
  y1 = std::min(y1, static_cast<int>(ny_) - 1);
  for (int y = y0; y <= y1; ++y) {
    uint64_t* row = bits_.data() + static_cast<std::size_t>(y) * words_;
    for (int w = x0 >> 6; w <= x1 >> 6; ++w) {
      const int lo = std::max(x0, w * 64) - w * 64, hi = std::min(x1, w * 64 + 63) - w * 64;
      row[w] |= (~uint64_t{0} >> (63 - hi)) & (~uint64_t{0} << lo);
    }
  }
}

void World::gatherSight(std::size_t chunk) {
  const std::size_t n = robots_.size();
  SightChunk& c = los_[chunk];
  c.clear();
  const Vec2 cache_center = cache_.center();
  const auto [first, end] = chunkSpan(chunk, n);
  c.block_end.resize(end - first);
  c.cache_end.resize(end - first);
  // Raw pointers and running counts: the loop mostly stores two counts per robot.
  uint32_t *const block_end = c.block_end.data(), *const cache_end = c.cache_end.data();
  const double *const x = robots_.x.data(), *const y = robots_.y.data();
  const uint8_t* const in_swarm = activeMask();  // null: all are
  uint32_t blocks = 0, caches = 0;
  for (std::size_t i = first; i < end; ++i) {
    // Out of the swarm, or where the mask says nothing is in sight: sees nothing.
    if ((!in_swarm || in_swarm[i]) && sight_.maySee(x[i], y[i])) {
      const Rect view = config_.sight.around(x[i], y[i]);
      sight_.forFreeBlocksIn(view, c.scratch, [&](int32_t b) {
        c.block_id.push_back(b);
        c.block_x.push_back(static_cast<float>(blocks_.x(b)));
        c.block_y.push_back(static_cast<float>(blocks_.y(b)));
      });
      if (cache_.exists() && view.overlaps(cache_.area())) {  // the cache is far larger than the view
        c.cache_id.push_back(0);
        c.cache_x.push_back(static_cast<float>(cache_center.x()));
        c.cache_y.push_back(static_cast<float>(cache_center.y()));
        c.cache_blocks.push_back(static_cast<uint32_t>(cache_.size()));
      }
      blocks = static_cast<uint32_t>(c.block_id.size());
      caches = static_cast<uint32_t>(c.cache_id.size());
    }
    block_end[i - first] = blocks;
    cache_end[i - first] = caches;
  }
}

void World::layOutSight(SensorData& out) {
  const std::size_t n = robots_.size(), n_chunks = los_.size();
  for (SightChunk* c = los_.data(); c != los_.data() + n_chunks; ++c) {
    const SightChunk* before = c == los_.data() ? nullptr : c - 1;
    c->block_at = before ? before->block_at + before->block_id.size() : 0;
    c->cache_at = before ? before->cache_at + before->cache_id.size() : 0;
  }
  const std::size_t blocks = n_chunks ? los_.back().block_at + los_.back().block_id.size() : 0;
  const std::size_t caches = n_chunks ? los_.back().cache_at + los_.back().cache_id.size() : 0;
  out.los_block_offset.resize(n + 1);
  out.los_cache_offset.resize(n + 1);
  out.los_block_offset[0] = out.los_cache_offset[0] = 0;
  out.los_block_id.resize(blocks);
  out.los_block_x.resize(blocks);
  out.los_block_y.resize(blocks);
  out.los_cache_id.resize(caches);
  out.los_cache_x.resize(caches);
  out.los_cache_y.resize(caches);
  out.los_cache_blocks.resize(caches);
}

void World::copySight(std::size_t chunk, SensorData& out) const {
  const SightChunk& c = los_[chunk];
  const std::size_t first = chunk * kChunk;
  for (std::size_t k = 0; k < c.block_end.size(); ++k) {
    out.los_block_offset[first + k + 1] = static_cast<uint32_t>(c.block_at + c.block_end[k]);
    out.los_cache_offset[first + k + 1] = static_cast<uint32_t>(c.cache_at + c.cache_end[k]);
  }
  const auto copy = [](const auto& from, auto& to, std::size_t at) {
    std::copy(from.begin(), from.end(), to.begin() + static_cast<std::ptrdiff_t>(at));
  };
  copy(c.block_id, out.los_block_id, c.block_at);
  copy(c.block_x, out.los_block_x, c.block_at);
  copy(c.block_y, out.los_block_y, c.block_at);
  copy(c.cache_id, out.los_cache_id, c.cache_at);
  copy(c.cache_x, out.los_cache_x, c.cache_at);
  copy(c.cache_y, out.los_cache_y, c.cache_at);
  copy(c.cache_blocks, out.los_cache_blocks, c.cache_at);
}

void World::SightChunk::clear() {
  for (auto* v : {&block_end, &cache_end, &cache_blocks}) v->clear();
  for (auto* v : {&block_id, &cache_id}) v->clear();
  for (auto* v : {&block_x, &block_y, &cache_x, &cache_y}) v->clear();
}

}  // namespace swarm_forage
