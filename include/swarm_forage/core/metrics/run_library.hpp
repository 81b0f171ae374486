#pragma once
// A library of finished runs and the paper's metrics of a run against it (docs/design-model.md, Metrics).
// ROS-free: the ROS layer fills it from bags and from live runs, and both the live topics and metrics/compute
// evaluate through evaluateRun(), so they agree exactly on the same runs.
//
// Runs are grouped by their identity: every parameter that changes the outcome except the seed
// (controller and its constants, arena geometry, swarm size, environment with all its parameters, run
// length, stepping mode, world constants, sample interval). Runs of one group differ only in seed; a
// group's series is the sample-by-sample mean over its runs (aggregateRuns). References of a group or
// live run share everything but the swarm size (or the environment):
//   scalability e        the group of the same controller, arena and environment at the next smaller N;
//   self-organization Z  that group (m_(i-1)) and the group at N = 1. With m_(i-1) > 1, P_lost(1, t)
//                        cancels from theta_Z in the paper's definitions, so Z needs no N = 1 run there
//                        (the status says so); authors_code_2019 then takes PL(1) as 0;
//   reactivity R, A      the ideal group (V = 0) of the same controller, arena and N.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/interval_metrics.hpp"
#include "swarm_forage/core/metrics/out_of_swarm.hpp"
#include "swarm_forage/core/metrics/swarm_metrics.hpp"
#include "swarm_forage/core/run/condition.hpp"

namespace swarm_forage {

/// A number in labels and problems as printf's %g writes it; `exact`: 17 digits, so that a table's value
/// equals the live topic's float64.
std::string numberText(double v, bool exact = false);
/// A CSV field in double quotes, inner quotes doubled (the tables' environment label, status).
std::string csvQuoted(const std::string& s);

/// Everything else of a run's identity: what must be equal for two runs, or a run and its references,
/// to be compared at all.
struct RunSetup {
  double arena_width = 0, arena_height = 0, cube_size = 0, ramp_length = 0;
  uint32_t n_blocks = 0;
  uint64_t ticks = 0;
  double ticks_per_second = 0;
  std::string mode = "lockstep";
  std::string world_constants, controller_constants;  // canonical "name=value" words
  uint32_t interval = 0;                              // the metrics' sample interval
  bool operator<(const RunSetup& o) const;
  bool operator==(const RunSetup& o) const { return !(*this < o) && !(o < *this); }
};

/// A run's identity; runs with equal keys differ only in seed.
struct RunKey {
  std::string controller, arena;
  uint32_t swarm_size = 0;
  Condition environment;  // as environment/throttle announced it at tick 0
  RunSetup setup;
  bool operator<(const RunKey& o) const;
  /// "crw 32x16 N=16 null" (what it measures; identity() tells setups apart)
  std::string label() const;
  /// Every field as canonical text (environment normalised: fields its waveform does not read dropped).
  std::string describe() const;
  /// 8 hex digits of a hash of describe() without the sample interval: what the world names bags by.
  std::string identity() const;
};

struct RunRecord {
  RunKey key;
  uint32_t seed = 0;
  std::string source;  // bag path, or "live run k"
  RunSeries series;
  uint32_t model_version = 0;  // world/provenance's; 0: not known (a live run, a bag older than provenance)
  std::optional<OutOfSwarm>
      out_of_swarm{};  // from world/population; nullopt: no population record, or not whole
};

/// One run seen twice: how RunLibrary::add resolved it.
struct AddResult {
  bool added = true;    // false: the library kept the run it had
  std::string problem;  // non-empty: a duplicate that is not the same record (report it)
};

/// Builds a run's series, sample by sample, from per-tick data.
class RunSeriesBuilder {
 public:
  RunSeriesBuilder(uint32_t interval, uint32_t swarm_size);
  /// Adds one tick; returns the sample it closes, if any (the series then holds it too).
  std::optional<IntervalSample> add(uint64_t tick, uint32_t delivered, uint64_t cumulative,
                                    uint32_t in_avoidance, bool last, double throttle);
  /// The open interval closed short (a run cut off); the series does not hold it.
  std::optional<IntervalSample> close(uint64_t tick, uint64_t cumulative) {
    return accumulator_.close(tick, cumulative);
  }
  const RunSeries& series() const { return series_; }
  bool finished() const { return finished_; }

 private:
  IntervalAccumulator accumulator_;
  RunSeries series_;
  bool finished_ = false;
};

/// The first `samples` samples of `r` (all of it when it is shorter): a reference cut to a running run's
/// length.
RunSeries firstSamples(const RunSeries& r, std::size_t samples);

/// A reference group, or why there is none.
struct Reference {
  const AggregatedRuns* runs = nullptr;  // null when missing
  std::string missing;                   // e.g. "no run of crw in 32x16 under null at N < 8 in the library"
};

class RunLibrary {
 public:
  /// Adds a run. Of two runs with the same key and seed, the first added is kept and the second is
  /// reported as a duplicate (problem), so a group never counts one seed twice nor loses one silently.
  /// Not duplicates: the same source read again (it replaces its earlier reading), and a live run and
  /// a bag with the same series (the run and its own recording: the bag is kept).
  AddResult add(const RunRecord& run);
  std::size_t size() const;
  const std::map<RunKey, AggregatedRuns>& groups() const { return groups_; }
  /// Runs of one group, in seed order.
  std::vector<const RunRecord*> runs(const RunKey& key) const;

  Reference smaller(const RunKey& key) const;  // same controller, arena, environment, next smaller N
  Reference single(const RunKey& key) const;   // same controller, arena, environment, N = 1
  Reference ideal(const RunKey& key) const;    // same controller, arena, N, ideal environment
  /// The group of `key` itself (normalised), named `description` when missing.
  Reference find(const RunKey& key, const std::string& description) const;
  /// The library with every group's runs drawn with replacement (as many as it has), each group from its own
  /// counter-based stream of (seed, identity, draw): one draw of the bootstrap over seeds
  /// (core/metrics/bootstrap).
  RunLibrary resampled(uint64_t seed, uint32_t draw) const;

 private:
  using Runs = std::map<RunKey, std::map<uint32_t, RunRecord>>;  // key -> seed -> run
  Reference lookup(const RunKey& wanted, const std::string& description) const;
  // Shared by copies (a bootstrap draw copies only the groups) and copied before a change (add).
  std::shared_ptr<Runs> runs_ = std::make_shared<Runs>();
  std::map<RunKey, AggregatedRuns> groups_;
};

/// A metric value with the reference it was computed against, or why it could not be.
struct Evaluated {
  bool valid = false;
  std::string status = "ok";  // the reason when invalid
  uint32_t reference_size = 0;
};

struct RunEvaluation {
  Evaluated scalability_status, self_organization_status, reactivity_status, adaptability_status;
  Scalability scalability;
  SelfOrganization self_organization;
  Flexibility reactivity, adaptability;
};

/// Evaluates `series` (a run of `key`, or a group's mean) against the library. While a run is going
/// (`final` false) the references are cut to its number of samples; at the end they are used whole.
RunEvaluation evaluateRun(const RunLibrary& library, const RunKey& key, const RunSeries& series, bool final,
                          Definitions defs, std::optional<std::size_t> band = std::nullopt);

/// The CSV tables of metrics/compute over every group of the library.
struct MetricTables {
  std::string scalability;            // e(N) per controller, arena, environment
  std::string self_organization;      // Z(N) likewise
  std::string flexibility;            // R, A per controller, arena, N, waveform, beta (non-ideal groups)
  std::string robustness;             // SAA and PD robustness per group with noise or population dynamics
  std::string robustness_runs;        // the same per run (its seed in place of the number of runs)
  std::vector<std::string> problems;  // groups whose metrics could not be computed, and why
};
MetricTables metricTables(const RunLibrary& library, Definitions defs,
                          std::optional<std::size_t> band = std::nullopt);

/// series.csv: each valid group's mean and 95 % confidence interval per sample; tick_end is the sample's
/// last tick (inclusive: interval - 1 for the first), as in metrics/performance.
std::string groupSeriesCsv(const RunLibrary& library);

}  // namespace swarm_forage
