#include "swarm_forage/core/run/run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <stdexcept>

#include "swarm_forage/core/controllers/controller_registry.hpp"

namespace swarm_forage {

namespace {
/// The words of `a` that `b` lacks: where two constants texts differ.
std::string wordsNotIn(const std::string& a, const std::string& b) {
  std::istringstream in(a);
  std::string out, word;
  while (in >> word)
    if ((" " + b + " ").find(" " + word + " ") == std::string::npos) out += (out.empty() ? "" : " ") + word;
  return out;
}

/// Who commands robot i: its range's controller, node and robots, from the tick's status (the run's
/// controller when no range reports the robot).
std::string commanderOf(uint32_t i, const std::vector<StatusRecord>& status, const RunDescription& d) {
  for (const StatusRecord& s : status)
    if (i >= s.first_id && i - s.first_id < s.count)
      return "controller '" + s.controller + "' (" + (s.source.empty() ? "" : "node " + s.source + ", ") +
             "robots [" + std::to_string(s.first_id) + ", " + std::to_string(s.first_id + s.count) + "))";
  return "controller '" + d.name() + "'";
}

std::string speedText(float v) {
  if (std::isnan(v)) return "nan";  // whatever its sign bit
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", static_cast<double>(v));
  return buf;
}

/// The world a run's controller needs; an external one (~external_controller) gets what every kind gets.
WorldConfig worldFor(const RunDescription& d) {
  if (d.external.empty() || d.controller != d.external) return configuredFor(d.world, d.controller);
  WorldConfig c = d.world;
  c.line_of_sight = false;
  c.cache.enabled = false;
  c.light_only_carrying = false;
  return c;
}
}  // namespace

Run::Run(RunDescription description, const RunSchedule& schedule, std::shared_ptr<WorkerPool> pool,
         ControllerPort& controllers, EnvironmentPort& environment, std::vector<RunSink*> sinks,
         std::string label)
    : description_(std::move(description)),
      schedule_(schedule),
      world_(worldFor(description_)),
      controllers_(controllers),
      environment_(environment),
      sinks_(std::move(sinks)),
      label_(std::move(label)) {
  world_.setPool(std::move(pool));
  description_.world = world_.config();
  description_.controller_constants.clear();
  description_.condition.reset();
  description_.fixed = false;
  // Records close before live views announce the end: the announcement names the bag.
  std::stable_partition(sinks_.begin(), sinks_.end(), [](const RunSink* s) { return s->isRecord(); });
}

RunEndRecord Run::execute(const Interrupt& interrupted) {
  StepOutcome outcome = StepOutcome::ok();
  try {
    if (!resumed_) begin();
    outcome = steps(interrupted);
  } catch (const std::exception& e) {
    end(StepOutcome::stop("error at tick " + std::to_string(world_.tick()) + ": " + e.what()));
    throw;
  }
  return end(outcome);
}

void Run::changeNoise(const SaaNoise& noise) {
  world_.setNoise(noise);
  for (RunSink* s : sinks_) s->noiseChanged(world_.tick(), noise);
}

void Run::begin() {
  for (RunSink* s : sinks_) s->begin(description_, label_);
  controllers_.begin(description_, world_);
}

StepOutcome Run::steps(const Interrupt& interrupted) {
  while (world_.tick() < description_.ticks) {
    const uint64_t tick = world_.tick();
    if (interrupted)
      if (StepOutcome why = interrupted(tick); why.stopped()) return why;
    world_.sense(sensors_);
    recordBeforeDecide(tick);
    if (StepOutcome decided = controllers_.decide(tick, world_, sensors_); decided.stopped()) return decided;
    const std::optional<ConditionSample> condition = environment_.condition(tick);
    if (!description_.fixed)
      if (StepOutcome fixed = fix(condition); fixed.stopped()) return fixed;
    TaskCounts tasks;
    for (const StatusRecord& s : controllers_.status()) {
      tasks.generalists += s.status.tasks.generalists;
      tasks.harvesters += s.status.tasks.harvesters;
      tasks.collectors += s.status.tasks.collectors;
    }
    if (StepOutcome bad = invalidCommand(tick); bad.stopped()) return bad;
    const Throttling throttle = condition ? condition->condition.throttling(condition->value) : Throttling{};
    const StepResult result = world_.step(controllers_.commands(), throttle, tasks);
    recordAfterStep(tick, condition, result.delivered);
    if (after_step_) after_step_(world_.tick());
  }
  return StepOutcome::ok();
}

StepOutcome Run::fix(const std::optional<ConditionSample>& condition) {
  // Each range names its controller: the announced kind, or the external one the world declared, which
  // must then serve a range too. One set of constants per controller; the identity holds each set.
  std::vector<std::string> kinds{description_.controller};
  if (!description_.external.empty() && description_.external != description_.controller)
    kinds.push_back(description_.external);
  std::map<std::string, std::string> served;  // controller -> the ranges reporting it
  for (const StatusRecord& s : controllers_.status()) {
    const std::string range =
        s.source + " [" + std::to_string(s.first_id) + ", " + std::to_string(s.first_id + s.count) + ")";
    if (std::find(kinds.begin(), kinds.end(), s.controller) == kinds.end())
      return StepOutcome::stop(
          "tick 0: " + range + " runs controller '" + s.controller + "', but the run is " +
          description_.name() +
          (kinds.size() > 1 ? " (~controller, ~external_controller)" : " (~controller)"));
    served[s.controller] += (served[s.controller].empty() ? "" : ", ") + range;
  }
  for (const std::string& kind : kinds)
    if (kinds.size() > 1 && served[kind].empty()) {
      const std::string& other = kinds[kind == kinds[0] ? 1 : 0];
      return StepOutcome::stop(
          "tick 0: no node runs controller " + kind + " of the run " + description_.name() +
          " (~controller, ~external_controller); every range runs " + other + ": " + served[other]);
    }
  std::string all;
  for (const std::string& kind : kinds) {
    std::map<std::string, std::string> constants;  // source -> the constants it reported
    for (const StatusRecord& s : controllers_.status())
      if (s.controller == kind && !s.constants.empty()) constants[s.source] = s.constants;
    for (const auto& [source, words] : constants)
      if (words != constants.begin()->second)
        return StepOutcome::stop("tick 0: the controller nodes run different constants (" +
                                 constants.begin()->first + ": " +
                                 wordsNotIn(constants.begin()->second, words) + "; " + source + ": " +
                                 wordsNotIn(words, constants.begin()->second) + "): one run needs one set");
    if (!constants.empty()) all += (all.empty() ? "" : " ") + constants.begin()->second;
  }
  description_.controller_constants = all;
  description_.condition = condition;
  description_.fixed = true;
  for (RunSink* s : sinks_) s->identityFixed(description_);
  return StepOutcome::ok();
}

StepOutcome Run::invalidCommand(uint64_t tick) const {
  // A NaN wheel speed would make every pose it touches NaN and still record a complete run; an unknown
  // request would be ignored. Every robot's command is checked, whichever port it came through.
  const CommandData& c = controllers_.commands();
  const std::size_t n = std::min({c.left.size(), c.right.size(), c.request.size()});
  bool bad = false;
  for (std::size_t i = 0; i < n; ++i)  // one pass without branches; the offender is looked for only then
    bad |= !std::isfinite(c.left[i]) | !std::isfinite(c.right[i]) | (c.request[i] > kCacheDrop);
  if (!bad) return StepOutcome::ok();
  for (std::size_t i = 0; i < n; ++i) {
    const auto robot = static_cast<uint32_t>(c.first_id + i);
    const std::string who = commanderOf(robot, controllers_.status(), description_),
                      at = " for robot " + std::to_string(robot) + " at tick " + std::to_string(tick);
    for (const auto& [wheel, v] : {std::pair<const char*, float>{"left", c.left[i]}, {"right", c.right[i]}})
      if (!std::isfinite(v))
        return StepOutcome::stop(who + " sent the " + wheel + " wheel speed " + speedText(v) + at +
                                 "; valid: a finite number of m/s (the world clamps it to [-" +
                                 canonicalNumber(world_.config().robot.max_speed) + ", " +
                                 canonicalNumber(world_.config().robot.max_speed) + "])");
    if (c.request[i] > kCacheDrop)
      return StepOutcome::stop(who + " sent the request code " + std::to_string(c.request[i]) + at +
                               "; valid: 0 to " + std::to_string(kCacheDrop) +
                               " (none, pickup, drop, cache pickup, cache drop)");
  }
  return StepOutcome::ok();
}

void Run::recordBeforeDecide(uint64_t tick) {
  for (RunSink* s : sinks_)
    if (tick % (s->isRecord() ? schedule_.record_every : schedule_.publish_every) == 0 && s->wantsSnapshot())
      s->snapshot(tick, sensors_, world_.blocks());
  if (!world_.config().cache.enabled) return;
  const auto state = std::make_pair(world_.cache().exists(), world_.cache().size());
  if (tick != 0 && state == cache_state_) return;
  cache_state_ = state;
  for (RunSink* s : sinks_) s->caches(tick, world_.cache());
}

void Run::recordAfterStep(uint64_t tick, const std::optional<ConditionSample>& condition,
                          uint32_t delivered) {
  PerformanceRecord p;
  p.tick = tick;
  p.run = description_.run;
  p.swarm_size = world_.config().n_robots;
  p.delivered = delivered;
  p.cumulative = world_.delivered();
  p.carrying = world_.carrying();
  p.throttle = condition ? condition->value : 0.0;
  p.last = tick + 1 == description_.ticks;
  const bool changed = condition && conditionChanged(*condition, recorded_condition_);
  if (world_.population().enabled()) {
    const PopulationRecord r = populationRecord(world_.population(), tick, description_.run, p.swarm_size);
    for (RunSink* s : sinks_) s->population(r);
  }
  for (RunSink* s : sinks_) {
    if (changed && s->isRecord()) s->condition(tick, *condition);
    s->stepped(controllers_.status(), p);
  }
}

RunEndRecord Run::end(const StepOutcome& outcome) {
  RunEndRecord end;
  end.run = description_.run;
  end.ticks_done = world_.tick();
  end.ticks = description_.ticks;
  end.complete = !outcome.stopped();
  end.reason = outcome.reason();
  end.identity = description_.identity();
  for (RunSink* s : sinks_) s->end(end);
  return end;
}

void OutcomeFile::end(RunEndRecord& end) {
  if (!path_.empty() && !appendOutcome(path_, end))
    throw std::runtime_error("cannot append to outcome " + path_);
}

}  // namespace swarm_forage
