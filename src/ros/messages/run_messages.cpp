#include "swarm_forage/ros/messages/run_messages.hpp"

#include "swarm_forage/core/run/model_version.hpp"
#include "swarm_forage/ros/messages/batch_messages.hpp"
#include "swarm_forage/ros/messages/condition_ros.hpp"
#include "swarm_forage/ros/runs/run_recorder.hpp"

namespace swarm_forage {

namespace {
// Each record and its message name their shared fields alike: one list per message, for both directions.
template <typename To, typename From>
void copyRunEnd(To& to, const From& from) {
  to.run = from.run;
  to.ticks_done = from.ticks_done;
  to.ticks = from.ticks;
  to.complete = from.complete;
  to.reason = from.reason;
  to.identity = from.identity;
  to.bag = from.bag;
}
template <typename To, typename From>
void copyStatus(To& to, const From& from) {
  to.tick = from.tick;
  to.run = from.run;
  to.first_id = from.first_id;
  to.count = from.count;
  to.swarm_size = from.swarm_size;
  to.controller = from.controller;
  to.constants = from.constants;
}
template <typename To, typename From>
void copyPerformance(To& to, const From& from) {
  to.tick = from.tick;
  to.run = from.run;
  to.swarm_size = from.swarm_size;
  to.delivered = from.delivered;
  to.cumulative = from.cumulative;
  to.carrying = from.carrying;
  to.throttle = from.throttle;
  to.last = from.last;
}
}  // namespace

NoiseChange noiseChangeMsg(uint32_t run, uint64_t tick, const SaaNoise& noise, uint64_t ns_per_tick) {
  NoiseChange msg;
  msg.header.stamp = tickTime(tick, ns_per_tick);
  msg.run = run;
  msg.tick = tick;
  msg.noise = noise.describe();
  return msg;
}

Provenance provenanceMsg(const std::string& label) {
  Provenance p;
  p.model_version = kModelVersion;
  p.code = codeDescription();
  p.label = label;
  return p;
}

Throttle throttleMsg(const ConditionSample& c, uint64_t ns_per_tick) {
  Throttle t;
  t.header.seq = c.seq;
  t.header.stamp = tickTime(c.tick, ns_per_tick);
  t.tick = c.tick;
  t.value = c.value;
  setCondition(t, c.condition);
  return t;
}

ConditionSample conditionSampleOf(const Throttle& t) {
  ConditionSample c;
  c.seq = t.header.seq;
  c.tick = t.tick;
  c.value = t.value;
  c.condition = conditionOf(t);
  return c;
}

Throttle throttleMsg(const Condition& condition, uint64_t tick, double ticks_per_second,
                     uint64_t ns_per_tick) {
  return throttleMsg(conditionAt(condition, tick, ticks_per_second), ns_per_tick);
}

SwarmStatus statusMsg(const ControllerStatus& status, const CommandData& commands, uint64_t tick,
                      uint32_t run, uint32_t swarm_size, const std::string& controller,
                      const ros::Time& stamp, const std::string& constants) {
  return statusMsg(statusRecord(status, commands, tick, run, swarm_size, controller, constants), stamp);
}

RunEnd runEndMsg(const RunEndRecord& e, uint64_t ns_per_tick) {
  RunEnd end;
  end.header.stamp = tickTime(e.ticks_done, ns_per_tick);
  copyRunEnd(end, e);
  return end;
}

RunEndRecord runEndOf(const RunEnd& msg) {
  RunEndRecord e;
  copyRunEnd(e, msg);
  return e;
}

SwarmStatus statusMsg(const StatusRecord& r, const ros::Time& stamp) {
  SwarmStatus msg;
  msg.header.seq = r.seq;
  msg.header.stamp = stamp;
  copyStatus(msg, r);
  toMsg(r.status, msg);
  return msg;
}

StatusRecord statusOf(const SwarmStatus& msg, const std::string& source) {
  StatusRecord r;
  copyStatus(r, msg);
  fromMsg(msg, r.status);
  r.source = source;
  r.seq = msg.header.seq;
  return r;
}

Performance performanceMsg(const PerformanceRecord& p, uint64_t ns_per_tick) {
  Performance perf;
  perf.header.stamp = tickTime(p.tick, ns_per_tick);
  copyPerformance(perf, p);
  return perf;
}

Population populationMsg(const PopulationRecord& p, uint64_t ns_per_tick) {
  Population msg;
  msg.header.stamp = tickTime(p.tick, ns_per_tick);
  msg.tick = p.tick;
  msg.run = p.run;
  msg.active = p.active;
  msg.present = p.present;
  msg.queue = p.queue;
  msg.max_size = p.max_size;
  msg.deaths = p.deaths;
  msg.births = p.births;
  msg.malfunctions = p.malfunctions;
  msg.repairs = p.repairs;
  msg.death = p.death;
  msg.birth = p.birth;
  msg.malfunction = p.malfunction;
  msg.repair = p.repair;
  msg.changed = p.changed;
  return msg;
}

PopulationRecord populationOf(const Population& msg) {
  PopulationRecord p;
  p.tick = msg.tick;
  p.run = msg.run;
  p.active = msg.active;
  p.present = msg.present;
  p.queue = msg.queue;
  p.max_size = msg.max_size;
  p.deaths = msg.deaths;
  p.births = msg.births;
  p.malfunctions = msg.malfunctions;
  p.repairs = msg.repairs;
  p.death = msg.death;
  p.birth = msg.birth;
  p.malfunction = msg.malfunction;
  p.repair = msg.repair;
  p.changed = msg.changed;
  return p;
}

PerformanceRecord performanceOf(const Performance& msg) {
  PerformanceRecord p;
  copyPerformance(p, msg);
  return p;
}

RunInfo runInfoMsg(const RunDescription& r, uint64_t ns_per_tick) {
  const WorldConfig& c = r.world;
  RunInfo info;
  info.header.stamp = tickTime(0, ns_per_tick);
  info.run = r.run;
  info.controller = r.name();
  info.arena = c.arena.name;
  info.arena_x = static_cast<float>(c.arena.width);
  info.arena_y = static_cast<float>(c.arena.height);
  info.swarm_size = c.n_robots;
  info.seed = c.seed;
  info.ticks = r.ticks;
  info.ticks_per_second = c.ticks_per_second;
  info.n_blocks = c.arena.n_blocks;
  info.cube_size = c.arena.cube_size;
  info.ramp_length = c.arena.ramp_length;
  info.mode = r.mode;
  info.world_constants = c.describeConstants();
  info.controller_constants = r.controller_constants;
  if (r.condition) info.environment = throttleMsg(*r.condition, ns_per_tick);
  if (info.environment.waveform.empty()) info.environment.waveform = "null";
  info.identity = r.key().identity();
  return info;
}

}  // namespace swarm_forage
