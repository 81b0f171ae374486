// The declaration of every parameter (param_table.hpp). A row is the one place of a name, its default and
// its range: the readers, --help, the known-parameter lists and the docs all take them from here.
#include "swarm_forage/ros/params/param_table.hpp"

#include <sstream>
#include <stdexcept>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/metrics/swarm_metrics.hpp"
#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/core/world/fordyca_quirks.hpp"
#include "swarm_forage/record/bag_writer.hpp"
#include "swarm_forage/ros/params/known_params.hpp"
#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

namespace {
using T = ParamType;
using List = std::vector<std::string>;
constexpr unsigned kWorld = kWorldNode, kController = kControllerNode, kEnvironment = kEnvironmentNode,
                   kMetrics = kMetricsNode, kHeadless = kRunExperiment;
constexpr double kNone = 0;  // lo and hi of a row without a range
constexpr double kTicks = 2000000000;

List models() { return modelNames(); }
List quirks() {
  List names;
  for (const QuirkInfo& q : quirkList()) names.emplace_back(q.name);
  return names;
}
List modes() { return {"lockstep", "realtime"}; }
List definitions() { return definitionsNames(); }

const std::vector<ParamSpec> kTable = {
    // The world's model: world_node and run_experiment (readWorldConfig).
    {"arena", T::kText, "32x16", kNone, kNone,
     "a name of config/arenas/*.yaml, or a path to an arena YAML file", nullptr,
     "the arena (config/arenas/*.yaml: 32x16, 64x32, 96x48)", kWorld | kHeadless},
    {"n_robots", T::kInt, "64", 1, 10000000, "(and as many as fit the arena's start region)", nullptr,
     "swarm size", kWorld | kHeadless},
    {"seed", T::kInt, "0", 0, kMaxSeed, "", nullptr, "the run's seed (world/reset takes the same range)",
     kWorld | kHeadless},
    {"ticks", T::kInt, "50000", 1, kTicks, "", nullptr, "run length in ticks",
     kWorld | kEnvironment | kHeadless},
    {"ticks_per_second", T::kNumber, "5", 0.001, 1000, "", nullptr, "simulated ticks per second",
     kWorld | kEnvironment | kHeadless},
    {"controller", T::kChoice, "crw", kNone, kNone,
     "or a plugin's <package>/<Class> (--controllers lists them)", controllerNames,
     "the controller kind (its registry says what the world runs for it)", kWorld | kController | kHeadless},
    {"external_controller", T::kText, "", kNone, kNone,
     "letters, digits and '_', not a controller of this build", nullptr,
     "a controller served by nodes outside this build (docs/rospy-controller.md)", kWorld},
    {"los_cell", T::kNumber, "0.2", 0.01, 10, "", nullptr, "line of sight: cell side [m]",
     kWorld | kHeadless},
    {"los_radius", T::kInt, "2", 0, 100, "", nullptr,
     "line of sight: the (2 radius + 1)^2 cells around a robot", kWorld | kHeadless},
    {"cache/size_fraction", T::kNumber, "0.1", 0.001, 1, "(and the cache fits between nest and source)",
     nullptr, "GP-DPO's static cache: its side as a fraction of the arena's width", kWorld | kHeadless},
    {"cache/block_fraction", T::kNumber, "0.1", 0.001, 1, "", nullptr,
     "a new cache holds floor(fraction x blocks) blocks", kWorld | kHeadless},
    {"cache/min_blocks", T::kInt, "2", 1, 1000, "", nullptr,
     "a pick-up leaving fewer blocks removes the cache", kWorld | kHeadless},
    {"cache/recreation_rate", T::kNumber, "0.05", 0, 100, "", nullptr,
     "P(re-create the cache in a tick) = 1 - exp(-rate H / C)", kWorld | kHeadless},
    {"serialize_block_ops", T::kBool, "false", kNone, kNone, "", nullptr,
     "FORDYCA's deconfliction: at most one pick-up and one nest drop finish per tick", kWorld | kHeadless},
    {"model", T::kChoice, "fordyca_2019", kNone, kNone, "", models,
     "the model: FORDYCA's code as it ran in 2019, or its corrections (docs/FIDELITY.md)",
     kWorld | kController | kHeadless},
    {"quirks", T::kText, "", kNone, kNone, "comma-separated quirks added to the model:", quirks,
     "FORDYCA quirks added to the model, one at a time for an ablation", kWorld | kController | kHeadless},
    {"population/death", T::kNumber, "0", 0, 1, "", nullptr, "population dynamics: death rate per tick",
     kWorld | kHeadless},
    {"population/birth", T::kNumber, "0", 0, 1, "", nullptr, "population dynamics: birth rate per tick",
     kWorld | kHeadless},
    {"population/malfunction", T::kNumber, "0", 0, 1, "", nullptr,
     "population dynamics: malfunction rate per tick", kWorld | kHeadless},
    {"population/repair", T::kNumber, "0", 0, 1, "", nullptr, "population dynamics: repair rate per tick",
     kWorld | kHeadless},
    {"population/max_size", T::kInt, "0", 0, 10000000, "(0 or n_robots)", nullptr,
     "population dynamics: most robots present (0: the swarm size)", kWorld | kHeadless},
    {"noise/", T::kSection, "off", kNone, kNone,
     "noise/<device>/{model,level}, noise/all/{model,level}, noise/ground/level (docs/robustness.md)",
     noiseParams, "sensor and actuator noise per device", kWorld | kHeadless},
    // world_node's own.
    {"mode", T::kChoice, "lockstep", kNone, kNone, "", modes,
     "lockstep: every tick waits for every reply; realtime: paced by the wall clock", kWorld},
    {"real_time_factor", T::kNumber, "1", 0.001, 1000, "", nullptr,
     "realtime mode: simulated seconds per wall second", kWorld},
    {"step_timeout", T::kNumber, "5", 0.01, 3600, "", nullptr,
     "longest wait for a tick's replies [s] before the run stops", kWorld},
    {"startup_timeout", T::kNumber, "30", 0.1, 3600, "", nullptr,
     "longest wait for the other nodes before tick 0 [s]", kWorld},
    {"wait_for_subscribers", T::kInt, "0", 0, 1000, "", nullptr,
     "world/performance subscribers to wait for before tick 0", kWorld},
    {"use_environment", T::kBool, "true", kNone, kNone, "", nullptr,
     "wait for environment/throttle every tick (false: V = 0)", kWorld},
    {"exit_when_done", T::kBool, "false", kNone, kNone, "", nullptr,
     "exit after the run instead of waiting for world/reset", kWorld},
    {"publish_every", T::kInt, "25", 1, 1000000, "", nullptr,
     "world/robots and world/blocks messages every that many ticks", kWorld},
    {"markers_rate", T::kNumber, "5", 0, 100, "", nullptr,
     "world/markers per wall second while someone subscribes (0: never)", kWorld},
    {"tf_robots", T::kText, "0", kNone, kNone, "a count in [0, 64] or a list of at most 64 robot ids",
     nullptr, "robots with a tf frame map -> robot_<id>, sent every tick", kWorld},
    // Where runs go: world_node and run_experiment (RunOutputs).
    {"record_every", T::kInt, "250", 1, 1000000, "", nullptr,
     "robot and block snapshots in the bag every that many ticks", kWorld | kHeadless},
    {"bag", T::kText, "", kNone, kNone, "a path", nullptr,
     "record the run to this bag (an existing one is refused unless overwrite)", kWorld | kHeadless},
    {"bag_dir", T::kText, "", kNone, kNone, "a folder", nullptr,
     "record each run into this folder, named by its identity", kWorld | kHeadless},
    {"overwrite", T::kBool, "false", kNone, kNone, "", nullptr, "replace an existing bag",
     kWorld | kHeadless},
    {"label", T::kText, "", kNone, kNone, "text", nullptr,
     "recorded in world/provenance (a sweep's record key)", kWorld | kHeadless},
    {"compression", T::kChoice, "none", kNone, kNone, "", BagWriter::compressionNames,
     "the bag's chunk compression", kWorld | kHeadless},
    {"outcome", T::kText, "", kNone, kNone, "a writable file path", nullptr,
     "append one YAML line per run: how it ended (what forage reads)", kWorld | kHeadless},
    {"threads", T::kInt, "0", 0, 256, "(0: one per core)", nullptr,
     "worker threads; every count gives the same bits", kWorld | kController | kHeadless},
    // controller_node's own; the constants are a section of every kind.
    {"first_id", T::kInt, "0", 0, 10000000, "", nullptr, "the first robot this node serves", kController},
    {"count", T::kInt, "0", 0, 10000000, "(0: all from first_id)", nullptr, "robots this node serves",
     kController},
    {"<kind>/", T::kSection, "config/controllers/<kind>.yaml", kNone, kNone,
     "each kind's constants; their ranges in config/controllers/*.yaml", controllerSections,
     "each controller kind's constants (crw/, dpo/, gp_dpo/ and the plugins')", kController | kHeadless},
    // The environmental condition: environment_node and run_experiment (readCondition; the core checks it).
    {"waveform", T::kCondition, "null", kNone, kNone, "", nullptr, "the condition's waveform over time",
     kEnvironment | kHeadless},
    {"beta", T::kCondition, "0", kNone, kNone, "", nullptr,
     "the condition's strength (the waveform's amplitude)", kEnvironment | kHeadless},
    {"alpha", T::kCondition, "-1", kNone, kNone, "", nullptr, "step_up, step_down: the step time [s]",
     kEnvironment | kHeadless},
    {"frequency", T::kCondition, "0.001", kNone, kNone, "", nullptr, "periodic waveforms: cycles per second",
     kEnvironment | kHeadless},
    {"phase", T::kCondition, "0", kNone, kNone, "", nullptr, "periodic waveforms: phase [rad]",
     kEnvironment | kHeadless},
    {"offset", T::kCondition, "0", kNone, kNone, "", nullptr, "periodic waveforms: V = offset + beta x shape",
     kEnvironment | kHeadless},
    {"target", T::kCondition, "carry_speed", kNone, kNone, "", nullptr, "what V acts on",
     kEnvironment | kHeadless},
    {"series", T::kCondition, "", kNone, kNone, "", nullptr, "series: the CSV file of t [s], V",
     kEnvironment | kHeadless},
    // metrics_node's; run_tables and read_run count runs as it does.
    {"sample_interval", T::kInt, "1000", 1, 100000000, "", nullptr, "a metrics sample every that many ticks",
     kMetrics | kRunTables | kReadRun},
    {"definitions", T::kChoice, "paper", kNone, kNone, "", definitions,
     "metric definitions (docs/metrics.md, Authors' code definitions)", kMetrics | kRunTables},
    {"dtw_band", T::kInt, "0", 0, 100000000, "(0: exact)", nullptr, "Sakoe-Chiba band of DTW in samples",
     kMetrics | kRunTables},
    {"library", T::kText, "", kNone, kNone, "a folder", nullptr,
     "run library: recorded runs, the references of e, Z, R and A", kMetrics},
    {"csv", T::kText, "", kNone, kNone, "a path", nullptr, "also append every sample to this CSV", kMetrics},
    {"exit_on_final", T::kBool, "false", kNone, kNone, "", nullptr, "exit after a run's final sample",
     kMetrics},
    // Health on /diagnostics (HealthReporter, readHealthThresholds).
    {"diagnostic_period", T::kNumber, "1", 0.05, 60, "", nullptr, "wall seconds between /diagnostics reports",
     kWorld | kController | kMetrics},
    {"diag_wait_warn", T::kNumber, "1", 0, 3600, "", nullptr,
     "/diagnostics WARN when a tick's replies take this long [s]", kWorld},
    {"diag_wait_error", T::kNumber, "3", 0, 3600, "(at least diag_wait_warn)", nullptr,
     "/diagnostics ERROR when a tick's replies take this long [s]", kWorld},
    {"diag_behind_warn", T::kNumber, "100", 0, 1e9, "", nullptr,
     "/diagnostics WARN when this many ticks wait for their messages", kMetrics},
    {"diag_behind_error", T::kNumber, "1000", 0, 1e9, "(at least diag_behind_warn)", nullptr,
     "/diagnostics ERROR when this many ticks wait for their messages", kMetrics},
    // run_experiment's own.
    {"progress", T::kInt, "0", 0, kTicks, "(0: none)", nullptr, "a line on stderr every that many ticks",
     kHeadless},
    {"checkpoint_every", T::kInt, "0", 0, kTicks, "(0: none)", nullptr,
     "write the run's whole state to checkpoint every that many ticks", kHeadless},
    {"checkpoint", T::kText, "", kNone, kNone, "a path (default with checkpoint_every: bag + .checkpoint)",
     nullptr, "the periodic checkpoint", kHeadless},
    {"save_at", T::kInt, "0", 0, kTicks, "(at most ticks; 0: none)", nullptr,
     "one checkpoint after that tick, to save (a fork's parent)", kHeadless},
    {"save", T::kText, "", kNone, kNone, "a path, not the checkpoint file", nullptr, "where save_at's goes",
     kHeadless},
    {"resume", T::kText, "", kNone, kNone, "a checkpoint file that checkpoint or save wrote", nullptr,
     "continue that run to ticks (another condition: a fork)", kHeadless},
    {"expect_identity", T::kText, "", kNone, kNone, "8 hex digits", nullptr,
     "refuse to run unless the run's identity is this (exit code 3; sweeps pass it)", kHeadless},
    // run_tables' and read_run's own.
    {"out", T::kText, "DIR", kNone, kNone, "a folder", nullptr, "where the tables go", kRunTables},
    {"bootstrap", T::kInt, "2000", 0, 100000, "", nullptr, "draws of the bootstrap over each group's seeds",
     kRunTables},
    {"bootstrap_seed", T::kInt, "1", 0, kMaxSeed, "", nullptr, "the bootstrap's seed", kRunTables},
    {"ticks", T::kBool, "false", kNone, kNone, "", nullptr, "also print each counted tick", kReadRun},
};
}  // namespace

const std::vector<ParamSpec>& paramTable() { return kTable; }

std::vector<ParamSpec> paramTable(ParamReader reader) {
  std::vector<ParamSpec> rows;
  for (const ParamSpec& s : kTable)
    if (s.readers & reader) rows.push_back(s);
  return rows;
}

const ParamSpec& paramSpec(const std::string& name, unsigned reader) {
  for (const ParamSpec& s : kTable)
    if (name == s.name && (reader == 0 || (s.readers & reader))) return s;
  throw std::logic_error("parameter " + name + " is not declared in src/ros/params/param_table.cpp");
}

namespace {
std::string number(double v) {
  std::ostringstream out;  // as the range messages print it
  out << v;
  return out.str();
}
}  // namespace

std::string validText(const ParamSpec& s) {
  std::string v;
  switch (s.type) {
    case T::kBool:
      return "true or false";
    case T::kInt:
      v = "a whole number in [" + std::to_string(static_cast<long long>(s.lo)) + ", " +
          std::to_string(static_cast<long long>(s.hi)) + "]";
      break;
    case T::kNumber:
      v = "a number in [" + number(s.lo) + ", " + number(s.hi) + "]";
      break;
    case T::kChoice:
      v = "one of " + joinNames(s.choices());
      break;
    case T::kCondition:
      for (const ConditionParameter& c : conditionParameters())
        if (c.name == s.name) return c.valid;
      throw std::logic_error(std::string("the core declares no condition parameter ") + s.name);
    case T::kText:
      return s.choices ? std::string(s.note) + " " + joinNames(s.choices()) : s.note;
    case T::kSection:
      return s.note;
  }
  return *s.note ? v + " " + s.note : v;
}

std::string fallbackText(const ParamSpec& s) { return *s.fallback ? s.fallback : "''"; }

std::vector<std::string> knownParams(ParamReader reader) {
  std::vector<std::string> names;
  for (const ParamSpec& s : kTable) {
    if (!(s.readers & reader)) continue;
    if (s.type != T::kSection) {
      names.emplace_back(s.name);
      continue;
    }
    for (const std::string& key : s.choices()) names.push_back(key);
  }
  return names;
}

namespace {
const std::vector<std::pair<ParamReader, const char*>> kReaders{{kWorldNode, "world_node"},
                                                                {kControllerNode, "controller_node"},
                                                                {kEnvironmentNode, "environment_node"},
                                                                {kMetricsNode, "metrics_node"},
                                                                {kRunExperiment, "run_experiment"},
                                                                {kRunTables, "run_tables"},
                                                                {kReadRun, "read_run"}};
}  // namespace

const char* readerName(ParamReader reader) {
  for (const auto& [r, name] : kReaders)
    if (r == reader) return name;
  return "";
}

unsigned readerNamed(const std::string& name) {
  for (const auto& [r, n] : kReaders)
    if (name == n) return r;
  return 0;
}

}  // namespace swarm_forage
