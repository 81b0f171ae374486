#pragma once
// Reading private ~parameters once, with validation that names the parameter and its valid range.
// A ParamSource is where they come from: a node's parameter server namespace, or (run_experiment, no
// master) name:=value words from the command line.
#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/core/world/config.hpp"
#include "swarm_forage/ros/params/param_table.hpp"

namespace swarm_forage {

constexpr int kMaxSeed = 2147483647;  // ~seed is an int parameter; world/reset takes the same range

/// What a reader accepts for one parameter: --help prints these, gathered from the code that validates.
struct ParamUsage {
  std::string name, fallback, valid, doc;
};

class ParamSource {
 public:
  virtual ~ParamSource() = default;
  /// Every reader (param, paramInRange, paramOneOf) tells what it accepts before it reads.
  virtual void accepts(const ParamUsage&) const {}
  /// False when `name` (slash-separated below the private namespace) is unset.
  virtual bool get(const std::string& name, XmlRpc::XmlRpcValue& value) const = 0;
  /// The full name, for messages.
  virtual std::string resolve(const std::string& name) const = 0;
};

/// A node's private ~parameters on the parameter server.
class NodeParams final : public ParamSource {
 public:
  explicit NodeParams(const ros::NodeHandle& pnh) : pnh_(pnh) {}
  bool get(const std::string& name, XmlRpc::XmlRpcValue& value) const override;
  std::string resolve(const std::string& name) const override { return pnh_.resolveName(name); }

 private:
  ros::NodeHandle pnh_;
};

/// Parameters without a master: `name:=value` words (values read as YAML scalars: 64 is an int, 0.5 a
/// double, true a bool, anything else a string; expect_identity and label always text), `name` possibly
/// nested (crw/wander_limit_deg).
class WordParams final : public ParamSource {
 public:
  /// Throws ParameterError for a word that is not name:=value.
  explicit WordParams(const std::vector<std::string>& words);
  bool get(const std::string& name, XmlRpc::XmlRpcValue& value) const override;
  std::string resolve(const std::string& name) const override { return name + ":="; }
  /// Names given that are not among `valid` (prefixes ending in '/' match whole sections).
  std::vector<std::string> unknown(const std::vector<std::string>& valid) const;
  void accepts(const ParamUsage& u) const override;
  /// What the readers accepted, in the order they read (the first reader of a name tells).
  const std::vector<ParamUsage>& usage() const { return usage_; }

 private:
  XmlRpc::XmlRpcValue root_;
  std::vector<std::string> names_;
  mutable std::vector<ParamUsage> usage_;
};

/// `usage` as aligned lines "  NAME  DEFAULT  VALID" under a header line, each followed by its doc when it
/// has one, for --help.
std::string usageTable(const std::vector<ParamUsage>& usage);
/// The rows of the parameter table (param_table.hpp) that `reader` reads, as usageTable lists them.
std::vector<ParamUsage> tableUsage(ParamReader reader);

/// Reads the parameter the table declares as `name` (param_table.hpp), with its default and its range; a
/// `reader` picks the row where two tools give one name two meanings (read_run's ticks). T: bool, int,
/// double or std::string, as the row's type.
template <typename T>
T readParam(const ParamSource& p, const std::string& name, unsigned reader = 0);
template <typename T>
T readParam(const ros::NodeHandle& pnh, const std::string& name) {
  return readParam<T>(NodeParams(pnh), name);
}
/// The row's default as a T.
template <typename T>
T fallbackOf(const ParamSpec& s);

/// Reads ~name (default when unset); throws ParameterError when it is set with the wrong type.
template <typename T>
T param(const ParamSource& p, const std::string& name, const T& fallback);
template <typename T>
T param(const ros::NodeHandle& pnh, const std::string& name, const T& fallback) {
  return param<T>(NodeParams(pnh), name, fallback);
}

/// Reads a number in [lo, hi]; throws ParameterError "~name must be in [lo, hi] (got v)".
double paramInRange(const ParamSource& p, const std::string& name, double fallback, double lo, double hi);
/// `value` of ~name when it is in [lo, hi]; else a ParameterError that says so (for live changes).
double valueInRange(const std::string& name, double value, double lo, double hi);
int paramInRange(const ParamSource& p, const std::string& name, int fallback, int lo, int hi);
/// Reads a string that must be one of `valid`.
std::string paramOneOf(const ParamSource& p, const std::string& name, const std::string& fallback,
                       const std::vector<std::string>& valid);

inline double paramInRange(const ros::NodeHandle& pnh, const std::string& name, double fallback, double lo,
                           double hi) {
  return paramInRange(NodeParams(pnh), name, fallback, lo, hi);
}
inline int paramInRange(const ros::NodeHandle& pnh, const std::string& name, int fallback, int lo, int hi) {
  return paramInRange(NodeParams(pnh), name, fallback, lo, hi);
}
inline std::string paramOneOf(const ros::NodeHandle& pnh, const std::string& name,
                              const std::string& fallback, const std::vector<std::string>& valid) {
  return paramOneOf(NodeParams(pnh), name, fallback, valid);
}

/// Resolves ~arena: a name of config/arenas/NAME.yaml or a path to a YAML file (arena_params.cpp).
ArenaConfig loadArena(const std::string& name_or_path);
/// The file ~arena names: config/arenas/NAME.yaml for a name, the value itself when it holds a '/' or a '.'.
std::string arenaFile(const std::string& name_or_path);
/// The names of config/arenas/*.yaml, sorted.
std::vector<std::string> arenaNames();

/// The world's model parameters (arena, n_robots, seed, ticks_per_second, cache/*, los_*,
/// serialize_block_ops), validated as world_node reads them.
WorldConfig readWorldConfig(const ParamSource& p);

/// ~model (swarm_forage or fordyca_2019) and ~quirks (comma-separated quirk names added on top), read alike
/// by world_node and controller_node: each applies its own side (docs/FIDELITY.md).
FordycaQuirks readQuirks(const ParamSource& p);

/// ~noise/<device>/model (gaussian or uniform) and ~noise/<device>/level for proximity, light, position,
/// heading and wheels, ~noise/ground/level (a misread probability), ~noise/all/{model,level} for every
/// device at once (noise_params.cpp). Off by default.
SaaNoise readNoise(const ParamSource& p);
/// Their names.
std::vector<std::string> noiseParams();

/// ~threads: worker threads for the world or a controller range, in [0, 256]; 0 (the default) = one per
/// core. Results do not depend on it.
unsigned readThreads(const ParamSource& p);

/// The environmental condition (~waveform, ~beta, ~alpha, ~frequency, ~phase, ~offset, ~target, ~series)
/// as a run of `ticks` applies it (Condition::forRun). Throws ParameterError naming the ~parameter.
Condition readCondition(const ParamSource& p, uint64_t ticks, double ticks_per_second);
/// The file a ~series names: as given when it exists there or holds a '/', else the file of that name in
/// the package's config/conditions when there is one (roslaunch starts nodes in ROS_HOME).
std::string seriesPath(const std::string& series);
/// `c` as a run of `ticks` applies it (alpha -1: half the run; a series read from seriesPath), checked by
/// the one rule of the core; the error names the ~parameter (a series file: its line). What readCondition
/// and dynamic_reconfigure both apply.
Condition conditionForRun(const Condition& c, uint64_t ticks, double ticks_per_second);

/// The controllers' constants (~crw/*, ~dpo/*, ~gp_dpo/*; defaults: the core's, which equal
/// config/controllers/*.yaml); an unknown key is an error that lists the valid ones.
ControllerConfigs readControllerConfigs(const ParamSource& p);
/// ~controller (default crw): a built-in kind or a plugin's "<package>/<Class>", loaded now; its
/// registered name; `external` (world_node's ~external_controller, served by nodes outside this build) is
/// taken as it is. Throws ParameterError listing every available kind for another name.
std::string paramController(const ParamSource& p, const std::string& external = "");
/// Loads the YAML defaults of the constants kind `kind` reads (ControllerKind::defaults) into pnh's
/// ~parameters not set yet, as launch/controller_params.launch loads the built-ins': a plugin's, which no
/// launch file names. They equal the code defaults (checked when a plugin loads).
void putControllerDefaults(const ros::NodeHandle& pnh, const std::string& kind);

}  // namespace swarm_forage
