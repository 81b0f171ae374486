#include "swarm_forage/core/run/run_records.hpp"

#include <cctype>
#include <fstream>

namespace swarm_forage {

PopulationRecord populationRecord(const PopulationDynamics& population, uint64_t tick, uint32_t run,
                                  uint32_t n_robots) {
  const PopulationEvents& e = population.events();
  PopulationRecord r;
  r.tick = tick;
  r.run = run;
  r.active = e.active;
  r.present = e.present;
  r.queue = e.queue;
  r.max_size = population.config().max_size ? population.config().max_size : n_robots;
  r.deaths = e.deaths;
  r.births = e.births;
  r.malfunctions = e.malfunctions;
  r.repairs = e.repairs;
  const PopulationConfig& rates = population.config();
  r.death = rates.death;
  r.birth = rates.birth;
  r.malfunction = rates.malfunction;
  r.repair = rates.repair;
  r.changed = population.changed();
  return r;
}

namespace {
std::string quotedYaml(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
  return out + "\"";
}

}  // namespace

ConditionSample conditionAt(const Condition& condition, uint64_t tick, double ticks_per_second) {
  return {tick, condition.value(static_cast<double>(tick) / ticks_per_second), condition};  // exact at alpha
}

bool conditionChanged(const ConditionSample& c, std::optional<ConditionSample>& last) {
  if (c.tick != 0 && last && last->value == c.value && last->condition == c.condition) return false;
  last = c;
  return true;
}

std::string RunDescription::name() const {
  return external.empty() || external == controller ? controller : controller + "+" + external;
}

RunKey RunDescription::key(uint32_t interval) const {
  RunKey key;
  key.controller = name();
  key.arena = world.arena.name;
  key.swarm_size = world.n_robots;
  RunSetup& s = key.setup;
  // The arena's size as world/run_info carries it (float32): a run and its record have one key.
  s.arena_width = static_cast<float>(world.arena.width);
  s.arena_height = static_cast<float>(world.arena.height);
  s.cube_size = world.arena.cube_size;
  s.ramp_length = world.arena.ramp_length;
  s.n_blocks = world.arena.n_blocks;
  s.ticks = ticks;
  s.ticks_per_second = world.ticks_per_second;
  s.mode = mode;
  s.world_constants = world.describeConstants();
  s.controller_constants = controller_constants;
  s.interval = interval;
  if (condition && !condition->condition.waveform.empty()) key.environment = condition->condition;
  return key;
}

std::string RunDescription::identity() const { return fixed ? key().identity() : ""; }

std::string fileSafe(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return s;
}

std::string runBagName(const RunDescription& r) {
  const std::string head =
      r.name() + "_" + r.world.arena.name + "_n" + std::to_string(r.world.n_robots) + "_";
  const std::string seed = "seed" + std::to_string(r.world.seed);
  if (!r.fixed) return fileSafe(head + seed + "_run" + std::to_string(r.run)) + ".bag";
  // What varies beside the condition, so that a record's name says what it is (its identity says exactly).
  std::string what = r.key().environment.normalized().tag();
  for (const std::string& tag : {r.world.noise.tag(), r.world.population.tag(), r.world.quirks.tag()})
    if (!tag.empty()) what += "_" + tag;
  return fileSafe(head + what + "_" + seed + "_" + r.identity()) + ".bag";
}

std::string runBagPath(const std::string& bag, const std::string& bag_dir, const RunDescription& r) {
  if (!bag_dir.empty()) return bag_dir + "/" + runBagName(r);
  if (bag.empty() || r.run == 0) return bag;
  return bag.substr(0, bag.rfind(".bag")) + "_run" + std::to_string(r.run) + ".bag";
}

StatusRecord statusRecord(const ControllerStatus& status, const CommandData& commands, uint64_t tick,
                          uint32_t run, uint32_t swarm_size, const std::string& controller,
                          const std::string& constants) {
  StatusRecord r;
  r.tick = tick;
  r.run = run;
  r.first_id = commands.first_id;
  r.count = static_cast<uint32_t>(commands.size());
  r.swarm_size = swarm_size;
  r.controller = controller;
  r.status = status;
  r.constants = constants;
  return r;
}

bool appendOutcome(const std::string& path, const RunEndRecord& end) {
  std::ofstream out(path, std::ios::app);
  out << "- {run: " << end.run << ", complete: " << (end.complete ? "true" : "false")
      << ", ticks_done: " << end.ticks_done << ", ticks: " << end.ticks
      << ", reason: " << quotedYaml(end.reason) << ", bag: " << quotedYaml(end.bag)
      << ", identity: " << quotedYaml(end.identity) << "}\n";
  return static_cast<bool>(out);
}

}  // namespace swarm_forage
