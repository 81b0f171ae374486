#include "swarm_forage/core/controllers/controller_factory.hpp"

#include "swarm_forage/core/controllers/parallel_batch.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

WorldConfig configuredFor(WorldConfig c, const std::string& controller) {
  c.line_of_sight = needsLineOfSight(controller);
  c.cache.enabled = needsStaticCache(controller);
  return c;
}

ControllerConfigs sharingWorld(ControllerConfigs c, const Vec2& nest_center, const LineOfSight& sight) {
  for (DpoConfig* d : {&c.dpo, &c.gp_dpo.dpo}) {
    d->nest_center = nest_center;
    d->los_cell = sight.cell;
    d->los_radius = sight.radius;
  }
  return c;
}

std::unique_ptr<ControllerBatch> makeController(const std::string& kind, const ControllerConfigs& configs,
                                                uint32_t seed, uint32_t first_id, uint32_t count,
                                                std::shared_ptr<WorkerPool> pool) {
  if (pool != nullptr && pool->threads() > 1) {
    auto part = [&](uint32_t first, uint32_t n) { return makeController(kind, configs, seed, first, n); };
    return std::make_unique<ParallelBatch>(part, first_id, count, std::move(pool));
  }
  if (kind == "crw") return std::make_unique<CrwBatch>(configs.crw, seed, first_id, count);
  if (kind == "dpo") return std::make_unique<DpoBatch>(configs.dpo, seed, first_id, count);
  if (kind == "gp_dpo") return std::make_unique<GpDpoBatch>(configs.gp_dpo, seed, first_id, count);
  throw ParameterError("controller '" + kind + "' is unknown; valid: crw, dpo, gp_dpo");
}

}  // namespace swarm_forage
