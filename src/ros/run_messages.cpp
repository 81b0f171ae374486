#include "swarm_forage/ros/run_messages.hpp"

#include <cctype>
#include <fstream>

#include "swarm_forage/core/run/model_version.hpp"
#include "swarm_forage/ros/convert.hpp"
#include "swarm_forage/ros/run_bag.hpp"
#include "swarm_forage/ros/run_recorder.hpp"

namespace swarm_forage {

namespace {
std::string quotedYaml(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
  return out + "\"";
}
}  // namespace

Provenance provenanceMsg(const std::string& label) {
  Provenance p;
  p.model_version = kModelVersion;
  p.code = codeDescription();
  p.label = label;
  return p;
}

RunEnd runEndMsg(uint32_t run, uint64_t ticks_done, uint64_t ticks, const std::string& reason,
                 const std::string& identity, uint64_t ns_per_tick) {
  RunEnd end;
  end.header.stamp = tickTime(ticks_done, ns_per_tick);
  end.run = run;
  end.ticks_done = ticks_done;
  end.ticks = ticks;
  end.complete = reason.empty();
  end.reason = reason;
  end.identity = identity;
  return end;
}

bool appendOutcome(const std::string& path, const RunEnd& end) {
  std::ofstream out(path, std::ios::app);
  out << "- {run: " << end.run << ", complete: " << (end.complete ? "true" : "false")
      << ", ticks_done: " << end.ticks_done << ", ticks: " << end.ticks
      << ", reason: " << quotedYaml(end.reason) << ", bag: " << quotedYaml(end.bag)
      << ", identity: " << quotedYaml(end.identity) << "}\n";
  return static_cast<bool>(out);
}

std::string fileSafe(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return s;
}

Throttle throttleMsg(const WaveformConfig& waveform, uint64_t tick, double ticks_per_second,
                     uint64_t ns_per_tick) {
  Throttle t;
  t.header.stamp = tickTime(tick, ns_per_tick);
  t.tick = tick;
  t.value = waveformValue(waveform, static_cast<double>(tick) / ticks_per_second);  // exact at alpha
  t.waveform = waveform.name;
  t.amplitude = waveform.amplitude;
  t.alpha = waveform.alpha;
  t.frequency = waveform.frequency;
  t.phase = waveform.phase;
  t.offset = waveform.offset;
  return t;
}

bool sameWaveform(const Throttle& a, const Throttle& b) {
  return a.waveform == b.waveform && a.amplitude == b.amplitude && a.alpha == b.alpha &&
         a.frequency == b.frequency && a.phase == b.phase && a.offset == b.offset;
}

bool recordThrottle(const Throttle& t, std::optional<Throttle>& last) {
  if (t.tick != 0 && last && last->value == t.value && sameWaveform(*last, t)) return false;
  last = t;
  return true;
}

SwarmStatus statusMsg(const ControllerStatus& status, const CommandData& commands, uint64_t tick,
                      uint32_t run, uint32_t swarm_size, const std::string& controller,
                      const ros::Time& stamp, const std::string& constants) {
  SwarmStatus msg;
  msg.header.stamp = stamp;
  msg.tick = tick;
  msg.run = run;
  msg.first_id = commands.first_id;
  msg.count = static_cast<uint32_t>(commands.size());
  msg.swarm_size = swarm_size;
  msg.controller = controller;
  toMsg(status, msg);
  msg.constants = constants;
  return msg;
}

Performance performanceMsg(const World& world, const StepResult& result, uint64_t tick, uint32_t run,
                           double throttle, bool last, const ros::Time& stamp) {
  Performance perf;
  perf.header.stamp = stamp;
  perf.tick = tick;
  perf.run = run;
  perf.swarm_size = world.config().n_robots;
  perf.delivered = result.delivered;
  perf.cumulative = world.delivered();
  perf.carrying = world.carrying();
  perf.throttle = throttle;
  perf.last = last;
  return perf;
}

RunInfo runInfoMsg(const WorldConfig& c, const std::string& controller, uint32_t run, uint64_t ticks,
                   const std::string& mode, const std::string& controller_constants,
                   const std::optional<Throttle>& throttle, uint64_t ns_per_tick) {
  RunInfo info;
  info.header.stamp = tickTime(0, ns_per_tick);
  info.run = run;
  info.controller = controller;
  info.arena = c.arena.name;
  info.arena_x = static_cast<float>(c.arena.width);
  info.arena_y = static_cast<float>(c.arena.height);
  info.swarm_size = c.n_robots;
  info.seed = c.seed;
  info.ticks = ticks;
  info.ticks_per_second = c.ticks_per_second;
  info.n_blocks = c.arena.n_blocks;
  info.cube_size = c.arena.cube_size;
  info.ramp_length = c.arena.ramp_length;
  info.mode = mode;
  info.world_constants = c.describeConstants();
  info.controller_constants = controller_constants;
  if (throttle) info.environment = *throttle;
  if (info.environment.waveform.empty()) info.environment.waveform = "null";
  info.identity = runKey(info, 0).identity();
  return info;
}

std::string runBagName(const RunInfo& info) {
  const Environment env = runKey(info, 0).environment;
  const std::string condition = env.ideal() ? "null" : env.waveform + canonicalNumber(env.beta);
  return fileSafe(info.controller + "_" + info.arena + "_n" + std::to_string(info.swarm_size) + "_" +
                  condition + "_seed" + std::to_string(info.seed) + "_" + info.identity) +
         ".bag";
}

}  // namespace swarm_forage
