// Line of sight for the DPO family: the blocks and caches whose centre lies in each robot's view.
#include "swarm_forage/core/world.hpp"

namespace swarm_forage {

void World::senseLineOfSight(SensorData& out) {
  const std::size_t n = robots_.size();
  out.clearLineOfSight();
  out.los_block_offset.assign(n + 1, 0);
  out.los_cache_offset.assign(n + 1, 0);
  const Vec2 cache_center = cache_.center();
  for (std::size_t i = 0; i < n; ++i) {
    const Rect view = config_.sight.around(robots_.x[i], robots_.y[i]);
    blocks_.forFreeBlocksIn(view, scratch_, [&](int32_t b) {
      out.los_block_id.push_back(b);
      out.los_block_x.push_back(static_cast<float>(blocks_.x(b)));
      out.los_block_y.push_back(static_cast<float>(blocks_.y(b)));
    });
    if (cache_.exists() && view.overlaps(cache_.area())) {  // the cache is far larger than the view
      out.los_cache_id.push_back(0);
      out.los_cache_x.push_back(static_cast<float>(cache_center.x()));
      out.los_cache_y.push_back(static_cast<float>(cache_center.y()));
      out.los_cache_blocks.push_back(static_cast<uint32_t>(cache_.size()));
    }
    out.los_block_offset[i + 1] = static_cast<uint32_t>(out.los_block_id.size());
    out.los_cache_offset[i + 1] = static_cast<uint32_t>(out.los_cache_id.size());
  }
}

}  // namespace swarm_forage
