#pragma once
// Builds a controller batch of a named kind with its configuration.
#include <memory>
#include <string>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/controllers/crw.hpp"
#include "swarm_forage/core/controllers/dpo.hpp"
#include "swarm_forage/core/controllers/gp_dpo.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

struct ControllerConfigs {
  CrwConfig crw;
  DpoConfig dpo;
  GpDpoConfig gp_dpo;
};

/// The world features a controller kind needs: line of sight, the static cache.
WorldConfig configuredFor(WorldConfig c, const std::string& controller);

/// The facts DPO-family robots share with their world: the nest centre and the line-of-sight geometry.
ControllerConfigs sharingWorld(ControllerConfigs c, const Vec2& nest_center, const LineOfSight& sight);

/// A batch for robots [first_id, first_id + count); throws ParameterError for an unknown kind. With a
/// pool of more than one thread, the range runs in parallel parts (same commands).
std::unique_ptr<ControllerBatch> makeController(const std::string& kind, const ControllerConfigs& configs,
                                                uint32_t seed, uint32_t first_id, uint32_t count,
                                                std::shared_ptr<WorkerPool> pool = nullptr);

}  // namespace swarm_forage
