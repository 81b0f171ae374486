#pragma once
// The controller kinds this build provides. A kind declares itself once, in its own .cpp, with one
// registration line (`const ControllerRegistrar registrar{...}`); every list of kinds, every check of a
// kind's name, the world features it needs, its constants' YAML section and its look in figures derive
// from here (docs/design-model.md, Controllers).
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/controllers/controller_constants.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

/// A controller batch that threw while being made or stepped: the message names the kind.
struct ControllerFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

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
  /// It reads the light sensor only while it carries a block (phototaxis to the nest). With the
  /// light_occlusion quirk the world then shadows only carriers' lights (WorldConfig).
  bool light_only_carrying = false;
  /// Its batches are stepped whole, on the calling thread, never split over the worker pool (an embedded
  /// interpreter's kinds: one thread may hold the interpreter at a time).
  bool one_thread = false;
  std::function<std::unique_ptr<ConstantSection>()> constants;  // its own section, at its defaults
  std::string
      defaults;  // its YAML defaults, relative to its package (built-ins: config/controllers/<name>.yaml)
  Make make;
};

/// Adds a kind: the one registration path, taken by a built-in's registrar at static initialisation and by
/// a plugin when the ROS layer loads it (controller_plugin.hpp). Throws std::logic_error for a kind
/// without name, constants or make, or a second kind of the same name.
void registerKind(ControllerKind kind);

/// Registers a built-in kind at static initialisation (`const ControllerRegistrar registrar{...}`).
struct ControllerRegistrar {
  explicit ControllerRegistrar(ControllerKind kind);
};

/// Where kinds that are not registered yet come from (the ROS layer: pluginlib). The core asks it for a
/// name it does not know; `load` registers the kind with registerKind and throws, naming it, when it
/// cannot.
class ControllerSource {
 public:
  virtual ~ControllerSource() = default;
  /// The names it could load, sorted.
  virtual std::vector<std::string> names() const = 0;
  /// Registers kind `name`; false when it has no such name.
  virtual bool load(const std::string& name) = 0;
};
/// Installs the source of further kinds, replacing every source added before.
void setControllerSource(std::shared_ptr<ControllerSource> source);
/// Adds a source of further kinds (pluginlib's, the embedded Python's): a name is asked of each in the order
/// they were added, and the first that loads it wins.
void addControllerSource(std::shared_ptr<ControllerSource> source);

/// The registered kinds' names, sorted (crw, dpo, gp_dpo, and the plugins loaded so far).
std::vector<std::string> controllerNames();
/// The registered kinds and those the source could load, sorted: what "valid: ..." lists.
std::vector<std::string> availableControllers();
/// The kind called `name`, loading it from the source if need be; "swarm_forage/<built-in>" is the
/// built-in. Throws ParameterError "controller 'x' is unknown; valid: ..." for another name.
const ControllerKind& controllerKind(const std::string& name);
/// The package a kind comes from: a plugin's "<package>/<Class>" prefix, else swarm_forage.
std::string controllerPackage(const ControllerKind& kind);
/// The constants' sections kind `name` reads: those of the kinds it builds on, base first, then its own.
std::vector<std::string> constantSections(const std::string& name);
/// Kind `name` as one entry of a YAML list for scripts (run_experiment --controllers): its name, look,
/// constants' sections, world features, whether it can be checkpointed, package and defaults file;
/// `package_path` turns a package name into its folder, for the defaults file.
std::string describeControllerKind(const std::string& name,
                                   const std::function<std::string(const std::string&)>& package_path = {});
/// Every registered kind, in the order of controllerNames(), as describeControllerKind gives each.
std::string describeControllerKinds(const std::function<std::string(const std::string&)>& package_path = {});
/// Whether kind `name`'s batches can be checkpointed (ControllerBatch::checkpointable of a one-robot batch
/// at the defaults); false for a kind whose batch cannot be made.
bool checkpointableKind(const std::string& name);

/// The world features a controller kind needs: line of sight, the static cache.
WorldConfig configuredFor(WorldConfig c, const std::string& controller);

/// The constants with the facts every batch learns from its world: the nest centre and the line of sight.
ControllerConfigs sharingWorld(ControllerConfigs c, const Vec2& nest_center, const LineOfSight& sight);

/// A batch for robots [first_id, first_id + count); throws ParameterError for an unknown kind. With a
/// pool of more than one thread, the range runs in parallel parts (same commands). An exception from the
/// kind's make or step comes out as ControllerFailure naming the kind.
std::unique_ptr<ControllerBatch> makeController(const std::string& kind, const ControllerConfigs& configs,
                                                uint32_t seed, uint32_t first_id, uint32_t count,
                                                std::shared_ptr<WorkerPool> pool = nullptr);

}  // namespace swarm_forage
