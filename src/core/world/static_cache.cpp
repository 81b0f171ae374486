#include "swarm_forage/core/world/static_cache.hpp"

#include <algorithm>
#include <cmath>

namespace swarm_forage {

Rect CacheConfig::area(const ArenaConfig& a) const {
  const Rect nest = a.nest(), source = a.source();
  const double cx = ((nest.min_x + nest.max_x) / 2 + (source.min_x + source.max_x) / 2) / 2;
  const double side = size_fraction * a.width;
  return Rect::centered(cx, a.height / 2, side, side);
}

uint32_t CacheConfig::initialBlocks(const ArenaConfig& a) const {
  return static_cast<uint32_t>(std::floor(block_fraction * a.n_blocks + 1e-9));
}

void CacheConfig::validate(const ArenaConfig& a) const {
  if (!enabled) return;
  const Rect r = area(a), nest = a.nest(), source = a.source();
  if (!(size_fraction > 0) || r.min_y < 0 || r.max_y > a.height || r.overlaps(nest) || r.overlaps(source))
    throw ParameterError("cache size_fraction must be in (0, " +
                         std::to_string(std::min((source.min_x - nest.max_x) / a.width, a.height / a.width)) +
                         "] so the cache fits between nest and source of a " + a.name + " arena (got " +
                         std::to_string(size_fraction) + ")");
  if (!(block_fraction > 0 && block_fraction <= 1))
    throw ParameterError("cache block_fraction must be in (0, 1] (got " + std::to_string(block_fraction) +
                         ")");
  if (min_blocks < 1 || min_blocks > 1000)
    throw ParameterError("cache min_blocks must be in [1, 1000] (got " + std::to_string(min_blocks) + ")");
  if (initialBlocks(a) < min_blocks)
    throw ParameterError(
        "cache block_fraction x blocks must give at least min_blocks = " + std::to_string(min_blocks) +
        " blocks (gives " + std::to_string(initialBlocks(a)) + ")");
  if (!(recreation_rate >= 0 && recreation_rate <= 100))
    throw ParameterError("cache recreation_rate must be in [0, 100] (got " + std::to_string(recreation_rate) +
                         ")");
}

void StaticCache::init(const ArenaConfig& arena, const CacheConfig& config) {
  config_ = config;
  capacity_ = config.initialBlocks(arena);
  area_ = config.area(arena);
  exists_ = false;
  blocks_.clear();
}

bool StaticCache::create(BlockField& field) {
  std::vector<int32_t> chosen;
  for (std::size_t b = 0; b < field.size() && chosen.size() < capacity_; ++b)
    if (field.carrier(static_cast<int32_t>(b)) == kFree) chosen.push_back(static_cast<int32_t>(b));
  if (chosen.size() < capacity_ || chosen.size() < config_.min_blocks) return false;
  const Vec2 c = center();
  for (int32_t b : chosen) field.stash(b, c.x(), c.y());
  blocks_ = chosen;
  exists_ = true;
  return true;
}

int32_t StaticCache::take(BlockField& field, int32_t robot) {
  if (!exists_ || blocks_.empty()) return -1;
  const int32_t b = blocks_.back();
  blocks_.pop_back();
  field.assign(b, robot);
  if (blocks_.size() < config_.min_blocks) {  // depleted: the rest become free blocks
    const Vec2 c = center();
    for (int32_t rest : blocks_) field.putDown(rest, c.x(), c.y());
    blocks_.clear();
    exists_ = false;
  }
  return b;
}

void StaticCache::put(BlockField& field, int32_t block) {
  const Vec2 c = center();
  field.stash(block, c.x(), c.y());
  blocks_.push_back(block);
}

double StaticCache::recreationProbability(uint32_t harvesters, uint32_t collectors) const {
  const double load = collectors == 0 ? harvesters : static_cast<double>(harvesters) / collectors;
  return 1.0 - std::exp(-config_.recreation_rate * load);
}

}  // namespace swarm_forage
