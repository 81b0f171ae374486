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
  out.clearLineOfSight();
  out.los_block_offset.assign(n + 1, 0);
  out.los_cache_offset.assign(n + 1, 0);
  std::size_t i = 0;
  for (std::size_t chunk = 0; chunk < n_chunks; ++chunk) {
    const SightChunk& c = los_[chunk];
    const auto blocks = static_cast<uint32_t>(out.los_block_id.size());
    const auto caches = static_cast<uint32_t>(out.los_cache_id.size());
    for (std::size_t k = 0; k < c.block_end.size(); ++k, ++i) {
      out.los_block_offset[i + 1] = blocks + c.block_end[k];
      out.los_cache_offset[i + 1] = caches + c.cache_end[k];
    }
    const auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
    append(out.los_block_id, c.block_id);
    append(out.los_block_x, c.block_x);
    append(out.los_block_y, c.block_y);
    append(out.los_cache_id, c.cache_id);
    append(out.los_cache_x, c.cache_x);
    append(out.los_cache_y, c.cache_y);
    append(out.los_cache_blocks, c.cache_blocks);
  }
}

void World::SightChunk::clear() {
  for (auto* v : {&block_end, &cache_end, &cache_blocks}) v->clear();
  for (auto* v : {&block_id, &cache_id}) v->clear();
  for (auto* v : {&block_x, &block_y, &cache_x, &cache_y}) v->clear();
}

}  // namespace swarm_forage
