#pragma once
// The controller kinds this build provides. A kind declares itself once, in its own .cpp, with one
// registration line (`const ControllerRegistrar registrar{...}`); every list of kinds, every check of a
// kind's name, the world features it needs, its constants' YAML section and its look in figures derive
// from here (docs/design.md, Controllers).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/controllers/controller_constants.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

struct ControllerKind {
  /// Builds a batch for robots [first_id, first_id + count) from every kind's constants (it may read
  /// those of the kind it builds on) and the world facts, when set.
  using Make = std::function<std::unique_ptr<ControllerBatch>(const ControllerConfigs& configs, uint32_t seed,
                                                              uint32_t first_id, uint32_t count)>;

  std::string name;            // ~controller value and YAML section ~<name>/; a plugin's: "<package>/<Class>"
  std::string display_name;    // in figures and tables
  std::string colour;          // in figures (a matplotlib colour)
  std::string builds_on;       // the kind whose constants it reads too ("": none); DPO explores like CRW
  bool line_of_sight = false;  // the world computes the blocks and caches each robot sees
  bool static_cache = false;   // the world runs the static cache
  std::function<std::unique_ptr<ConstantSection>()> constants;  // its own section, at its defaults
  std::string defaults;  // its YAML defaults, relative to its package (built-ins: config/controllers/<name>.yaml)
  Make make;
};

/// Registers a kind at static initialisation (a second kind of the same name is a programming error).
struct ControllerRegistrar {
  explicit ControllerRegistrar(ControllerKind kind);
};

/// The registered kinds' names, sorted (crw, dpo, gp_dpo).
const std::vector<std::string>& controllerNames();
/// The kind called `name`; throws ParameterError "controller 'x' is unknown; valid: ..." for another name.
const ControllerKind& controllerKind(const std::string& name);
/// The constants' sections kind `name` reads: those of the kinds it builds on, base first, then its own.
std::vector<std::string> constantSections(const std::string& name);
/// Every kind, in the order of controllerNames(), as YAML for scripts (run_experiment --controllers).
std::string describeControllerKinds();

/// The world features a controller kind needs: line of sight, the static cache.
WorldConfig configuredFor(WorldConfig c, const std::string& controller);

/// The constants with the facts every batch learns from its world: the nest centre and the line of sight.
ControllerConfigs sharingWorld(ControllerConfigs c, const Vec2& nest_center, const LineOfSight& sight);

/// A batch for robots [first_id, first_id + count); throws ParameterError for an unknown kind. With a
/// pool of more than one thread, the range runs in parallel parts (same commands).
std::unique_ptr<ControllerBatch> makeController(const std::string& kind, const ControllerConfigs& configs,
                                                uint32_t seed, uint32_t first_id, uint32_t count,
                                                std::shared_ptr<WorkerPool> pool = nullptr);

}  // namespace swarm_forage
