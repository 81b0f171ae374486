// Line of sight for the DPO family: the blocks and caches whose centre lies in each robot's view. Chunks
// of robots fill their own lists in parallel; the lists are then joined in robot order.
#include <algorithm>

#include "swarm_forage/core/world.hpp"

namespace swarm_forage {

void World::senseLineOfSight(SensorData& out) {
  const std::size_t n = robots_.size();
  const std::size_t n_chunks = chunks(n);
  los_.resize(n_chunks);
  const Vec2 cache_center = cache_.center();
  pool_->run(n_chunks, [&](std::size_t chunk, unsigned) {
    SightChunk& c = los_[chunk];
    c.clear();
    const std::size_t first = chunk * kChunk, end = std::min(n, first + kChunk);
    for (std::size_t i = first; i < end; ++i) {
      const Rect view = config_.sight.around(robots_.x[i], robots_.y[i]);
      blocks_.forFreeBlocksIn(view, c.scratch, [&](int32_t b) {
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
      c.block_end.push_back(static_cast<uint32_t>(c.block_id.size()));
      c.cache_end.push_back(static_cast<uint32_t>(c.cache_id.size()));
    }
  });
  // Where each chunk's lists start in the joined ones, then every chunk copies its own in parallel.
  std::vector<std::size_t> block_at(n_chunks + 1, 0), cache_at(n_chunks + 1, 0);
  for (std::size_t chunk = 0; chunk < n_chunks; ++chunk) {
    block_at[chunk + 1] = block_at[chunk] + los_[chunk].block_id.size();
    cache_at[chunk + 1] = cache_at[chunk] + los_[chunk].cache_id.size();
  }
  out.los_block_offset.resize(n + 1);
  out.los_cache_offset.resize(n + 1);
  out.los_block_offset[0] = out.los_cache_offset[0] = 0;
  out.los_block_id.resize(block_at.back());
  out.los_cache_id.resize(cache_at.back());
  for (auto* v : {&out.los_block_x, &out.los_block_y}) v->resize(block_at.back());
  for (auto* v : {&out.los_cache_x, &out.los_cache_y}) v->resize(cache_at.back());
  out.los_cache_blocks.resize(cache_at.back());
  pool_->run(n_chunks, [&](std::size_t chunk, unsigned) {
    const SightChunk& c = los_[chunk];
    const std::size_t first = chunk * kChunk;
    for (std::size_t k = 0; k < c.block_end.size(); ++k) {
      out.los_block_offset[first + k + 1] = static_cast<uint32_t>(block_at[chunk] + c.block_end[k]);
      out.los_cache_offset[first + k + 1] = static_cast<uint32_t>(cache_at[chunk] + c.cache_end[k]);
    }
    const auto copy = [](const auto& from, auto& to, std::size_t at) {
      std::copy(from.begin(), from.end(), to.begin() + at);
    };
    copy(c.block_id, out.los_block_id, block_at[chunk]);
    copy(c.block_x, out.los_block_x, block_at[chunk]);
    copy(c.block_y, out.los_block_y, block_at[chunk]);
    copy(c.cache_id, out.los_cache_id, cache_at[chunk]);
    copy(c.cache_x, out.los_cache_x, cache_at[chunk]);
    copy(c.cache_y, out.los_cache_y, cache_at[chunk]);
    copy(c.cache_blocks, out.los_cache_blocks, cache_at[chunk]);
  });
}

void World::SightChunk::clear() {
  for (auto* v : {&block_end, &cache_end, &cache_blocks}) v->clear();
  for (auto* v : {&block_id, &cache_id}) v->clear();
  for (auto* v : {&block_x, &block_y, &cache_x, &cache_y}) v->clear();
}

}  // namespace swarm_forage
