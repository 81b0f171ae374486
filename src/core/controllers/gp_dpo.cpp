#include "swarm_forage/core/controllers/gp_dpo.hpp"

#include <cmath>
#include <limits>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/controllers/task_allocation.hpp"
#include "swarm_forage/core/util/rng.hpp"

namespace swarm_forage {

namespace {
void requireRange(double lo, double hi, const char* lo_what, const char* hi_what) {
  requireParameter(lo > 0 && lo <= hi, lo_what);
  requireParameter(hi <= 1e9, hi_what);
}

const std::vector<std::string>& stateNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = dpoStateNames();
    n.insert(n.end(), {"cache_pickup", "cache_drop", "abort_drop"});
    return n;
  }();
  return names;
}

// DPO's transitions and actions serve GP-DPO's states of the same name.
#define SAME_STATE(s) static_assert(static_cast<int>(GpDpoState::s) == static_cast<int>(DpoState::s), #s)
SAME_STATE(kExplore);
SAME_STATE(kVector);
SAME_STATE(kPickup);
SAME_STATE(kTransport);
SAME_STATE(kNestWander);
SAME_STATE(kDrop);
SAME_STATE(kLeaveNest);
#undef SAME_STATE
static_assert(static_cast<int>(GpDpoState::kCachePickup) == static_cast<int>(DpoState::kCount),
              "GP-DPO's own states follow DPO's");
DpoState asDpo(GpDpoState s) { return static_cast<DpoState>(s); }

ControllerKind gpDpoKind() {
  ControllerKind k;
  k.name = "gp_dpo";
  k.light_only_carrying = true;  // phototaxis in transport only
  k.display_name = "GP-DPO";
  k.colour = "tab:green";
  k.defaults = "config/controllers/gp_dpo.yaml";
  k.builds_on = "dpo";
  k.line_of_sight = true;
  k.static_cache = true;
  k.constants = sectionOf(visitGpDpoParameters);
  k.make = [](const ControllerConfigs& c, uint32_t seed, uint32_t first_id, uint32_t count) {
    GpDpoConfig config = c.of<GpDpoConfig>("gp_dpo");
    config.dpo = dpoConfig(c);
    return std::make_unique<GpDpoBatch>(config, seed, first_id, count);
  };
  return k;
}
const ControllerRegistrar registrar{gpDpoKind()};
}  // namespace

const char* gpDpoStateName(GpDpoState s) { return stateNames()[static_cast<std::size_t>(s)].c_str(); }

void visitGpDpoParameters(GpDpoConfig& c, ConstantVisitor& v) {
  v.choice("estimates", c.time_varying, "ideal", "time_varying");
  v.number("ideal_generalist_min", c.ideal_generalist_min);
  v.number("ideal_generalist_max", c.ideal_generalist_max);
  v.number("ideal_subtask_min", c.ideal_subtask_min);
  v.number("ideal_subtask_max", c.ideal_subtask_max);
  v.number("ideal_partition_reactivity", c.ideal_partition_reactivity);
  v.number("varying_generalist_min", c.varying_generalist_min);
  v.number("varying_generalist_max", c.varying_generalist_max);
  v.number("varying_subtask_min", c.varying_subtask_min);
  v.number("varying_subtask_max", c.varying_subtask_max);
  v.number("varying_partition_reactivity", c.varying_partition_reactivity);
  v.number("ema_weight", c.ema_weight);
  v.number("partition_initial", c.partition_initial);
  v.number("subtask_reactivity", c.subtask_reactivity);
  v.number("subtask_offset", c.subtask_offset);
  v.number("abort_reactivity", c.abort_reactivity);
  v.number("abort_offset", c.abort_offset);
}

void GpDpoConfig::validate() const {
  const auto require = requireParameter;
  dpo.validate();
  requireRange(ideal_generalist_min, ideal_generalist_max,
               "gp_dpo/ideal_generalist_min must be in (0, ideal_generalist_max]",
               "gp_dpo/ideal_generalist_max must be in [ideal_generalist_min, 1e9] ticks");
  requireRange(ideal_subtask_min, ideal_subtask_max,
               "gp_dpo/ideal_subtask_min must be in (0, ideal_subtask_max]",
               "gp_dpo/ideal_subtask_max must be in [ideal_subtask_min, 1e9] ticks");
  requireRange(varying_generalist_min, varying_generalist_max,
               "gp_dpo/varying_generalist_min must be in (0, varying_generalist_max]",
               "gp_dpo/varying_generalist_max must be in [varying_generalist_min, 1e9] ticks");
  requireRange(varying_subtask_min, varying_subtask_max,
               "gp_dpo/varying_subtask_min must be in (0, varying_subtask_max]",
               "gp_dpo/varying_subtask_max must be in [varying_subtask_min, 1e9] ticks");
  require(ideal_partition_reactivity >= 0 && ideal_partition_reactivity <= 100,
          "gp_dpo/ideal_partition_reactivity must be in [0, 100]");
  require(varying_partition_reactivity >= 0 && varying_partition_reactivity <= 100,
          "gp_dpo/varying_partition_reactivity must be in [0, 100]");
  require(ema_weight >= 0 && ema_weight <= 1, "gp_dpo/ema_weight must be in [0, 1]");
  require(partition_initial >= 0 && partition_initial <= 1, "gp_dpo/partition_initial must be in [0, 1]");
  require(subtask_reactivity >= 0 && subtask_reactivity <= 100,
          "gp_dpo/subtask_reactivity must be in [0, 100]");
  require(subtask_offset >= 0 && subtask_offset <= 100, "gp_dpo/subtask_offset must be in [0, 100]");
  require(abort_reactivity >= 0 && abort_reactivity <= 100, "gp_dpo/abort_reactivity must be in [0, 100]");
  require(abort_offset >= 0 && abort_offset <= 100, "gp_dpo/abort_offset must be in [0, 100]");
}

const char* gpTaskName(GpTask t) {
  static const char* names[] = {"generalist", "harvester", "collector", "none"};
  return names[static_cast<int>(t)];
}

GpDpoBatch::GpDpoBatch(const GpDpoConfig& config, uint32_t seed, uint32_t first_id, uint32_t count)
    : DpoBatch(config.dpo, seed, first_id, count),
      gp_(config),
      task_(count, static_cast<uint8_t>(GpTask::kNone)),
      last_subtask_(count, static_cast<uint8_t>(GpTask::kNone)),
      task_start_(count, 0),
      est_(count),
      partition_(count, config.partition_initial),
      caches_(count) {
  gp_.validate();
  for (uint32_t l = 0; l < count; ++l) seedEstimates(l);
}

void GpDpoBatch::seedEstimates(uint32_t l) {
  CounterRng rng = rngAt(l, kSeedTick);
  est_[l][GpTask::kGeneralist] = rng.uniform(gp_.generalistMin(), gp_.generalistMax());
  est_[l][GpTask::kHarvester] = rng.uniform(gp_.subtaskMin(), gp_.subtaskMax());
  est_[l][GpTask::kCollector] = rng.uniform(gp_.subtaskMin(), gp_.subtaskMax());
}

void GpDpoBatch::restart(uint32_t l) {
  DpoBatch::restart(l);
  task_[l] = last_subtask_[l] = static_cast<uint8_t>(GpTask::kNone);
  task_start_[l] = 0;
  seedEstimates(l);
  partition_[l] = gp_.partition_initial;
  caches_.clear(l);
}

void GpDpoBatch::assignTask(uint32_t l, GpTask task, uint64_t tick) {
  task_[l] = static_cast<uint8_t>(task);
  task_start_[l] = tick;
  if (task == GpTask::kHarvester || task == GpTask::kCollector) last_subtask_[l] = static_cast<uint8_t>(task);
}

void GpDpoBatch::updateCaches(uint32_t l, uint32_t i, const SensorData& s, uint32_t b, uint32_t e) {
  const Rect sight =
      s.los_cache_offset.size() > i + 1u ? certainSight(los_, s.x[i], s.y[i]) : Rect{0, 0, 0, 0};
  caches_.update(l, pheromone_, sight, s.los_cache_id.data() + b, s.los_cache_x.data() + b,
                 s.los_cache_y.data() + b, e - b, -1);
}

const Remembered* GpDpoBatch::selectCache(uint32_t l, uint32_t i, const SensorData& s) const {
  const auto& known = caches_.of(l);
  const int k = bestByUtility(known, Vec2(s.x[i], s.y[i]), config_.nest_center, 0.0);
  return k < 0 ? nullptr : &known[static_cast<std::size_t>(k)];
}

void GpDpoBatch::allocate(uint32_t l, uint64_t tick, CounterRng& rng) {
  GpTask next = GpTask::kGeneralist;
  if (partition_[l] > rng.uniform()) {
    const auto last = static_cast<GpTask>(last_subtask_[l]);
    if (last == GpTask::kNone) {
      next = rng.uniform() < 0.5 ? GpTask::kHarvester : GpTask::kCollector;
    } else {
      const GpTask other = last == GpTask::kHarvester ? GpTask::kCollector : GpTask::kHarvester;
      const double p =
          subtaskSwitchProbability(est_[l][last], est_[l][other], gp_.subtask_reactivity, gp_.subtask_offset);
      next = p > rng.uniform() ? other : last;
    }
  }
  assignTask(l, next, tick);
}

void GpDpoBatch::endTask(uint32_t l, uint64_t tick, CounterRng& rng) {
  const GpTask t = task(l);
  if (t != GpTask::kNone) {
    TaskEstimates& e = est_[l];
    e[t] = emaUpdate(e[t], static_cast<double>(tick - task_start_[l]), gp_.ema_weight);
    partition_[l] = partitionProbability(e[GpTask::kGeneralist], e[GpTask::kHarvester], e[GpTask::kCollector],
                                         gp_.partitionReactivity());
  }
  allocate(l, tick, rng);
}

void GpDpoBatch::acquireCache(uint32_t l, uint32_t i, const SensorData& s) {
  if (s.ground[i] == kCacheGround) {
    enter(l, GpDpoState::kCachePickup);
    return;
  }
  const Remembered* c = selectCache(l, i, s);
  if (state(l) == GpDpoState::kVector && c != nullptr && distance(s, i, *c) <= config_.arrival_tolerance) {
    caches_.forget(l, c->id);  // at its centre, but no cache under the robot
    c = selectCache(l, i, s);
  }
  enter(l, c != nullptr ? GpDpoState::kVector : GpDpoState::kExplore);
}

void GpDpoBatch::transition(uint32_t l, uint32_t i, uint64_t tick, const SensorData& s, CounterRng& rng) {
  const GpTask t = task(l);
  const bool carrying = s.carried_block[i] >= 0;
  const uint8_t ground = s.ground[i], events = s.events[i];
  switch (state(l)) {
    case GpDpoState::kExplore:
    case GpDpoState::kVector:
    case GpDpoState::kPickup:
      if (t == GpTask::kCollector)
        acquireCache(l, i, s);
      else
        DpoBatch::transition(l, i, s);
      break;
    case GpDpoState::kTransport:
      if (t != GpTask::kHarvester) {
        DpoBatch::transition(l, i, s);
      } else if (ground == kCacheGround) {
        enter(l, GpDpoState::kCacheDrop);
      } else if (const Remembered* c = selectCache(l, i, s)) {
        if (distance(s, i, *c) <= config_.arrival_tolerance) caches_.forget(l, c->id);
      }
      break;
    case GpDpoState::kDrop:
      DpoBatch::transition(l, i, s);
      if (state(l) == GpDpoState::kLeaveNest) endTask(l, tick, rng);  // delivered to the nest
      break;
    case GpDpoState::kCachePickup:
      if (carrying || (events & kPickupDone)) {
        enter(l, GpDpoState::kTransport);
      } else if ((events & kBlockVanished) || ground != kCacheGround) {
        if (events & kBlockVanished) {
          if (const Remembered* c = selectCache(l, i, s)) caches_.forget(l, c->id);
        }
        enter(l, GpDpoState::kExplore);
      }
      break;
    case GpDpoState::kCacheDrop:
      if (!carrying || (events & kDropDone)) {
        endTask(l, tick, rng);  // harvested into the cache
        enter(l, GpDpoState::kExplore);
      } else if (ground != kCacheGround) {
        enter(l, GpDpoState::kTransport);
      }
      break;
    case GpDpoState::kAbortDrop:
      if (!carrying || (events & kDropDone)) enter(l, GpDpoState::kExplore);
      break;
    default:  // nest wander, leave nest: FORDYCA leaves by wandering (base_foraging_fsm ST_LEAVING_NEST)
      DpoBatch::transition(l, i, s);
      break;
  }
}

static_assert(static_cast<uint8_t>(GpTask::kNone) == kTaskNone, "CommandData::task holds GpTask values");

void GpDpoBatch::step(uint64_t tick, const SensorData& s, CommandData& out, ControllerStatus& status) {
  prepare(out, status, stateNames());
  beginDrives();
  task_counts_ = TaskCounts{};
  driveAll(tick, s, config_.explore, out, status);  // chooseDrives() per strip, then the strip's drives
  status.tasks.generalists += task_counts_.generalists;
  status.tasks.harvesters += task_counts_.harvesters;
  status.tasks.collectors += task_counts_.collectors;
}

void GpDpoBatch::chooseDrives(uint32_t first, uint32_t end, uint64_t tick, const SensorData& s,
                              CommandData& out) {
  for (uint32_t l = first; l < end; ++l) {
    if (idle(l, s, out)) {
      request_[l] = kStill;
      continue;
    }
    const uint32_t i = first_id_ + l;
    // The estimates are read only at the interface (a robot in three): too sparse for the hardware's
    // prefetcher, and from memory each tick.
    if (l + kAhead < end) __builtin_prefetch(&est_[l + kAhead]);
    blocks_.prefetch(l + kAhead);
    caches_.prefetch(l + kAhead);
    observeBlocks(l, i, s);
    observeCaches(l, i, s);
    CounterRng rng = rngAt(l, tick);
    if (task(l) == GpTask::kNone) allocate(l, tick, rng);
    transition(l, i, tick, s, rng);
    if (atInterface(l) && task_start_[l] != tick) {
      const double u = rng.uniform();
      if (aborts(u, static_cast<double>(tick - task_start_[l]), est_[l][task(l)], gp_.abort_reactivity,
                 gp_.abort_offset)) {
        endTask(l, tick, rng);
        if (s.carried_block[i] >= 0)
          enter(l, GpDpoState::kAbortDrop);
        else if (state(l) != GpDpoState::kLeaveNest)
          enter(l, GpDpoState::kExplore);
      }
    }
    // Where vectoring heads: a cache for collectors (and harvesters carrying), else the target block.
    const GpDpoState st = state(l);
    const bool to_cache = (st == GpDpoState::kVector && task(l) == GpTask::kCollector) ||
                          (st == GpDpoState::kTransport && task(l) == GpTask::kHarvester);
    const Remembered* g =
        to_cache ? selectCache(l, i, s) : (st == GpDpoState::kVector ? blocks_.find(l, target_[l]) : nullptr);
    const Vec2 goal = g != nullptr ? Vec2(g->x, g->y) : Vec2(0, 0);
    uint8_t& request = request_[l];
    request = kNone;
    switch (st) {  // GP-DPO's own states: stopped (beginDrives' zero wheels), requesting
      case GpDpoState::kCachePickup:
        request = kCachePickup;
        break;
      case GpDpoState::kCacheDrop:
        request = kCacheDrop;
        break;
      case GpDpoState::kAbortDrop:
        request = kDrop;
        break;
      default:
        if (to_cache && g == nullptr)  // no cache known: explore (carrying, for a harvester)
          driveMotion(l, Motion::kExplore, s, rng);
        else
          act(l, i, tick, s, asDpo(st), g != nullptr ? &goal : nullptr, rng, request);
        break;
    }
  }
  // Each robot's task, by compares: tasks are mixed, so branches or a count by index (a chain through
  // memory) cost more. A robot out of the swarm has kTaskNone, as idle() left it.
  const uint8_t *const tasks = task_.data(), *const request = request_.data();
  uint8_t* const out_task = out.task.data();
  uint32_t generalists = 0, harvesters = 0, collectors = 0;
  for (uint32_t l = first; l < end; ++l) {
    const bool on = request[l] != kStill;
    const uint8_t t = on ? tasks[l] : kTaskNone;
    out_task[l] = t;
    generalists += t == static_cast<uint8_t>(GpTask::kGeneralist);
    harvesters += t == static_cast<uint8_t>(GpTask::kHarvester);
    collectors += t == static_cast<uint8_t>(GpTask::kCollector);
  }
  task_counts_.generalists += generalists;
  task_counts_.harvesters += harvesters;
  task_counts_.collectors += collectors;
}

}  // namespace swarm_forage
