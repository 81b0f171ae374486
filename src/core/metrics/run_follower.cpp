#include "swarm_forage/core/metrics/run_follower.hpp"

#include <stdexcept>

namespace swarm_forage {

namespace {
constexpr std::size_t kMaxPendingTicks = 5000;  // live: beyond this a tick is declared incomplete

/// `what` ("the environment") was changed by hand at `tick` to `to`.
std::string changedLive(uint64_t tick, const std::string& what, const std::string& to) {
  return what + " was changed live at tick " + std::to_string(tick) + " (to " + to +
         "): a run changed by hand is no reference";
}
}  // namespace

RunFollower::RunFollower(uint32_t interval, Mode mode, Listener* listener)
    : interval_(interval), mode_(mode), listener_(listener ? listener : &silent_) {
  RunSeriesBuilder check(interval, 0);  // refuses interval 0 here rather than at the first tick
}

void RunFollower::describe(uint32_t run, const AnnouncedRun& description) {
  descriptions_[run] = {description, false};
  drain(false);
}

bool RunFollower::follow(uint32_t run, uint64_t tick) {
  // A newer run, or (a world restarted, a bag replayed again) any run from tick 0 once the followed one
  // has finished or been abandoned.
  const bool fresh = !run_ || run > run_->number || (run_->finished && (run != run_->number || tick == 0));
  if (!fresh) return run == run_->number;
  if (run_ && !run_->finished)
    abandon("run " + std::to_string(run) + " started before it reached its last tick");
  start(run);
  return true;
}

void RunFollower::start(uint32_t run) {
  run_.emplace();
  run_->number = run;
  next_tick_.reset();
  if (mode_ == Mode::kRecord) next_tick_ = 0;
  pending_.clear();
  stale_.clear();
  last_counted_.reset();
}

void RunFollower::abandon(const std::string& why) {
  if (!run_ || run_->finished) return;
  listener_->warn("run " + std::to_string(run_->number) + " stopped at tick " +
                  std::to_string(next_tick_.value_or(0)) + " without its final tick (" + why +
                  "): left out of the library");
  run_->finished = true;
  pending_.clear();
}

void RunFollower::end(const RunEndRecord& e) {
  end_ = e;
  if (run_ && e.run == run_->number && !e.complete) abandon(e.reason);
}

void RunFollower::condition(const ConditionSample& applied) {
  // A condition changed by hand (dynamic_reconfigure): the series still follows the V applied, but the
  // run must not become a reference.
  if (!run_ || run_->finished || !run_->changed_live.empty() || !run_->description) return;
  if (applied.condition == run_->description->key.environment) return;
  run_->changed_live = changedLive(applied.tick, "the environment", applied.condition.label());
  listener_->warn("run " + std::to_string(run_->number) + ": " + run_->changed_live);
}

void RunFollower::handChanged(uint32_t run, uint64_t tick, const std::string& what, const std::string& to) {
  if (!follow(run, tick) || run_->finished || !run_->changed_live.empty()) return;
  run_->changed_live = changedLive(tick, what, to);
  listener_->warn("run " + std::to_string(run_->number) + ": " + run_->changed_live);
}

void RunFollower::population(const PopulationRecord& p) {
  // Also after the run's last performance: a tick's population record may come after it.
  if (follow(p.run, p.tick)) run_->out_of_swarm.add(p);
}

bool RunFollower::claimDescription() {
  if (run_->description) return true;
  const auto it = descriptions_.find(run_->number);
  if (it == descriptions_.end() || it->second.second) return false;
  it->second.second = true;
  run_->description = it->second.first;
  run_->builder.emplace(interval_, run_->description->key.swarm_size);
  listener_->described(*run_);
  return true;
}

RunFollower::Pending& RunFollower::pending(uint64_t tick, uint32_t swarm_size) {
  auto [it, fresh] = pending_.try_emplace(tick);
  if (fresh) it->second.status.begin(swarm_size);
  return it->second;
}

void RunFollower::performance(const PerformanceRecord& p, uint64_t stamp_ns) {
  // world/performance comes once per tick from one world: tick 0 of the followed run again, or of an
  // earlier run number, while the followed run is unfinished is a world started afresh (the last one was
  // interrupted; run numbers start at 0 again). Its earlier swarm/status waited in stale_.
  if (run_ && !run_->finished && p.tick == 0 &&
      (p.run < run_->number || (p.run == run_->number && next_tick_ && *next_tick_ > 0))) {
    auto early = std::move(stale_);
    abandon("a world started run " + std::to_string(p.run) + " from tick 0");
    start(p.run);
    next_tick_ = 0;
    for (const StatusRecord& s : early)
      if (s.run == p.run) status(s);
  }
  if (!follow(p.run, p.tick) || run_->finished) return;
  if (next_tick_ && p.tick >= *next_tick_) stale_.clear();  // the followed world is alive
  if (!next_tick_) {
    next_tick_ = p.tick;
    if (p.tick != 0)
      listener_->warn("joined run " + std::to_string(p.run) + " at tick " + std::to_string(p.tick) +
                      "; intervals count from there");
  }
  if (p.tick < *next_tick_) return;
  run_->swarm_size = p.swarm_size;
  Pending& pending_tick = pending(p.tick, p.swarm_size);
  pending_tick.performance = p;
  pending_tick.stamp_ns = stamp_ns;
  drain(false);
}

void RunFollower::status(const StatusRecord& s) {
  if (!follow(s.run, s.tick) || (next_tick_ && s.tick < *next_tick_)) {
    // Perhaps the first ticks of a world started afresh: kept until its world/performance tells.
    if (run_ && !run_->finished && stale_.size() < kMaxPendingTicks) stale_.push_back(s);
    return;
  }
  if (run_->finished) return;
  Pending& p = pending(s.tick, s.swarm_size);
  if (p.status.add(s.first_id, s.count, s.source) == RangeCoverage::Added::kNew) {
    p.in_avoidance += s.status.in_avoidance;
    p.covered += s.count;
    ++p.ranges;
  }
  drain(false);
}

void RunFollower::drain(bool force) {
  while (run_ && !run_->finished && next_tick_ && !pending_.empty()) {
    auto it = pending_.find(*next_tick_);
    const bool described = claimDescription();
    const bool complete =
        it != pending_.end() && it->second.performance && it->second.status.complete() && described;
    if (!complete) {
      // A record must be whole (record() says why it is not); live, a node may have died.
      if (mode_ == Mode::kRecord || (!force && pending_.size() < kMaxPendingTicks)) return;
      listener_->error("tick " + std::to_string(*next_tick_) + " never completed (" +
                       (it == pending_.end()            ? "nothing arrived"
                        : !it->second.performance       ? "no world/performance"
                        : !it->second.status.complete() ? it->second.status.missing()
                                                        : "no world/run_info for this run") +
                       "); counting it with what arrived");
      if (it == pending_.end() || !it->second.performance) {
        if (it != pending_.end()) pending_.erase(it);
        ++*next_tick_;
        continue;
      }
      if (!run_->builder) run_->builder.emplace(interval_, run_->swarm_size);
    }
    count(it->second);
    pending_.erase(it);
    ++*next_tick_;
  }
}

void RunFollower::count(Pending& pending) {
  const PerformanceRecord& p = *pending.performance;
  last_counted_.emplace(p, pending.stamp_ns);
  ++run_->ticks_seen;
  run_->in_avoidance_total += pending.in_avoidance;
  listener_->counted(*run_, JoinedTick{p, pending.in_avoidance, pending.covered, pending.ranges});
  const auto sample =
      run_->builder->add(p.tick, p.delivered, p.cumulative, pending.in_avoidance, p.last, p.throttle);
  if (!sample) return;
  if (sample->final) run_->finished = true;
  listener_->sample(*run_, *sample, pending.stamp_ns);
}

void RunFollower::flush() {
  if (mode_ != Mode::kLive || !run_ || run_->finished) return;
  drain(true);
  if (run_->finished || !run_->builder || !last_counted_) return;
  const auto& [last, stamp_ns] = *last_counted_;
  if (const auto cut = run_->builder->close(last.tick, last.cumulative))
    listener_->sample(*run_, *cut, stamp_ns);
}

std::string RunFollower::tickProblem(const RunKey& key) const {
  const uint64_t next = next_tick_.value_or(0);
  const auto it = pending_.lower_bound(next);
  if (it == pending_.end())
    return "the run stops at tick " + std::to_string(next) + " of " + std::to_string(key.setup.ticks) +
           " (incomplete)";
  const std::string at = "tick " + std::to_string(it->first) + ": ";
  if (!it->second.performance) return at + "no world/performance";
  if (it->first != next)
    return "ticks " + std::to_string(next) + " to " + std::to_string(it->first - 1) + " are missing";
  return at + "swarm/status covers " + std::to_string(it->second.covered) + " of " +
         std::to_string(key.swarm_size) + " robots";
}

RunRecord RunFollower::record(const std::string& source) const {
  const AnnouncedRun* d = run_ && run_->description ? &*run_->description : nullptr;
  if (!d && !descriptions_.empty()) {  // described, but no tick of it came
    const auto it = run_ ? descriptions_.find(run_->number) : descriptions_.begin();
    if (it != descriptions_.end()) d = &it->second.first;
  }
  if (!d) throw std::runtime_error("no world/run_info in the bag (was it recorded by world_node?)");
  if (!end_)
    throw std::runtime_error(
        "no world/run_end in the bag: its writer never closed it (killed?), so it is incomplete");
  if (!end_->complete)
    throw std::runtime_error("incomplete: run " + std::to_string(end_->run) + " stopped at tick " +
                             std::to_string(end_->ticks_done) + " of " + std::to_string(end_->ticks) + " (" +
                             end_->reason + ")");
  if (run_ && !run_->changed_live.empty()) throw std::runtime_error(run_->changed_live);
  if (!run_ || !run_->builder || !run_->builder->finished()) throw std::runtime_error(tickProblem(d->key));
  RunRecord r;
  r.key = d->key;
  r.seed = d->seed;
  r.source = source;
  r.series = run_->builder->series();
  r.model_version = model_version_;
  r.out_of_swarm = run_->out_of_swarm.totals(d->key.setup.ticks);
  return r;
}

}  // namespace swarm_forage
