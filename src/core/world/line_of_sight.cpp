// Line of sight for the DPO family: the blocks and caches whose centre lies in each robot's view. Each
// chunk of robots gathers its own lists (in parallel with sensing), then copies them into its place in
// the joined lists, robot order.
#include <algorithm>

#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

void World::gatherSight(std::size_t chunk) {
  const std::size_t n = robots_.size();
  SightChunk& c = los_[chunk];
  c.clear();
  const Vec2 cache_center = cache_.center();
  const auto [first, end] = chunkSpan(chunk, n);
  for (std::size_t i = first; i < end; ++i) {
    if (!active(i)) {  // out of the swarm: sees nothing
      c.block_end.push_back(static_cast<uint32_t>(c.block_id.size()));
      c.cache_end.push_back(static_cast<uint32_t>(c.cache_id.size()));
      continue;
    }
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
