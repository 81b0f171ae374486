#pragma once
// Following a run: each tick's world/performance joined with its swarm/status ranges into the run's
// series (interval_metrics), and the condition applied checked against the one announced. ROS-free:
// metrics_node (live or from a replayed bag), readRunBag and read_run feed it the same messages, so a
// run is counted one way only (docs/design-model.md, One metrics path). It takes the run engine's own records
// (run_records.hpp), so each message has one core form.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/run_library.hpp"
#include "swarm_forage/core/run/range_coverage.hpp"
#include "swarm_forage/core/run/run_records.hpp"

namespace swarm_forage {

/// What world/run_info announces: the run's identity (cut at the follower's interval) and seed.
struct AnnouncedRun {
  RunKey key;
  uint32_t seed = 0;
};

/// One tick as counted: its world/performance and what its swarm/status ranges add up to.
struct JoinedTick {
  PerformanceRecord performance;
  uint32_t in_avoidance = 0;  // summed over the ranges that answered
  uint32_t covered = 0;       // robots the ranges cover (the swarm size when whole)
  uint32_t ranges = 0;
};

/// The run being followed.
struct FollowedRun {
  uint32_t number = 0, swarm_size = 0;
  std::optional<AnnouncedRun> description;  // once world/run_info is in
  std::optional<RunSeriesBuilder> builder;  // its series so far
  bool finished = false;                    // its final tick counted, or abandoned
  uint64_t ticks_seen = 0, in_avoidance_total = 0;
  std::string changed_live;        // why it is no reference: its condition (or noise) was changed mid-run
  OutOfSwarmCounter out_of_swarm;  // its world/population records
};

class RunFollower {
 public:
  enum class Mode {
    kLive,   // metrics_node: joins a run at any tick; a tick still incomplete when 5000 wait is counted
             // with what arrived (a node died), and flush() counts the rest
    kRecord  // a recorded run as a library record: every tick from 0, each whole (record() says why not)
  };
  /// What the owner does with what the follower finds; every method is optional.
  class Listener {
   public:
    virtual ~Listener() = default;
    virtual void described(const FollowedRun&) {}  // the run's world/run_info was taken
    virtual void counted(const FollowedRun&, const JoinedTick&) {}
    virtual void sample(const FollowedRun&, const IntervalSample&, uint64_t /*stamp_ns*/) {}
    virtual void warn(const std::string&) {}
    virtual void error(const std::string&) {}
  };

  RunFollower(uint32_t interval, Mode mode, Listener* listener = nullptr);
  uint32_t interval() const { return interval_; }

  void describe(uint32_t run, const AnnouncedRun& description);
  /// world/performance; `stamp_ns` (its message's stamp) is handed back with the samples it closes.
  void performance(const PerformanceRecord& p, uint64_t stamp_ns);
  /// swarm/status of one range; a range two senders (StatusRecord::source) claim is counted once.
  void status(const StatusRecord& s);
  /// environment/throttle: the condition applied from its tick on.
  void condition(const ConditionSample& applied);
  void end(const RunEndRecord& e);
  /// world/provenance: the model version that made the runs followed from now on (their records carry it).
  void provenance(uint32_t model_version) { model_version_ = model_version; }
  /// Something of run `run` other than its condition was changed by hand at `tick` (`what`, e.g. "the
  /// noise", to `to`; world/noise): the run is no reference from then on.
  void handChanged(uint32_t run, uint64_t tick, const std::string& what, const std::string& to);
  /// world/population: the robots out of the swarm this tick (the run's record carries their totals).
  void population(const PopulationRecord& p);
  /// No more messages (a bag read to its end). Live: every waiting tick is counted with what arrived and
  /// an open interval is closed short (a sample the series does not hold), as a replay would have.
  void flush();

  /// kRecord: the followed run as a library record; throws std::runtime_error saying why it is none
  /// (no world/run_info or world/run_end, stopped early, changed live, a tick missing or not whole).
  RunRecord record(const std::string& source) const;

  const FollowedRun* run() const { return run_ ? &*run_ : nullptr; }
  /// Ticks with messages that are not yet counted: a follower falling behind.
  std::size_t waiting() const { return pending_.size(); }

 private:
  struct Pending {
    std::optional<PerformanceRecord> performance;
    uint64_t stamp_ns = 0;
    RangeCoverage status{"swarm/status"};
    uint32_t in_avoidance = 0, covered = 0, ranges = 0;
  };
  /// Follows a new run when (run, tick) starts one; false for a message of an older run.
  bool follow(uint32_t run, uint64_t tick);
  void start(uint32_t run);
  /// Drops the followed run, which will never have its final tick, saying so.
  void abandon(const std::string& why);
  /// Takes this run's description once it has arrived.
  bool claimDescription();
  Pending& pending(uint64_t tick, uint32_t swarm_size);
  void drain(bool force);
  void count(Pending& p);
  std::string tickProblem(
      const RunKey& key) const;  // kRecord: the first tick keeping the run from being whole

  uint32_t interval_;
  uint32_t model_version_ = 0;
  Mode mode_;
  Listener* listener_;
  Listener silent_;
  std::map<uint32_t, std::pair<AnnouncedRun, bool>> descriptions_;  // run -> (latest, already taken)
  std::optional<RunEndRecord> end_;                                 // the last world/run_end
  std::optional<FollowedRun> run_;
  std::optional<uint64_t> next_tick_;
  std::map<uint64_t, Pending> pending_;
  std::optional<std::pair<PerformanceRecord, uint64_t>> last_counted_;  // and its stamp: where a run cut
                                                                        // short ends (flush)
  // swarm/status older than the followed tick, kept while the followed run has stopped advancing: if
  // a world restarts (tick 0 again), they belong to its new run.
  std::vector<StatusRecord> stale_;
};

}  // namespace swarm_forage
