#pragma once
// Per-interval P(N,t), p(N,t), n_ca(N,t) and the speed condition s(t) from per-tick performance,
// interference and throttle V.
#include <cstdint>
#include <optional>
#include <ostream>

namespace swarm_forage {

struct IntervalSample {
  uint64_t tick_end = 0;  // last tick of the interval (inclusive)
  uint32_t interval_ticks = 0;
  uint64_t cumulative = 0;       // P(N, t)
  uint32_t delivered = 0;        // p(N, t)
  double mean_in_avoidance = 0;  // n_ca(N, t)
  double speed = 1;              // s(t) = 1 - mean V over the interval's ticks
  bool final = false;
};

/// Samples as CSV (metrics_node's ~csv, read_run): the header line, and one row of run `run`.
constexpr const char* kSampleCsvHeader = "run,swarm_size,tick_end,interval_ticks,P,p,n_ca,s,final\n";
void writeSampleRow(std::ostream& out, uint32_t run, uint32_t swarm_size, const IntervalSample& s);

class IntervalAccumulator {
 public:
  explicit IntervalAccumulator(uint32_t interval_ticks);
  /// Adds one tick; returns a sample when the tick closes an interval or is the run's last.
  std::optional<IntervalSample> add(uint64_t tick, uint32_t delivered, uint64_t cumulative,
                                    uint32_t in_avoidance, bool last, double throttle = 0.0);
  /// Closes the open interval short at `tick` (not final): a run cut off before its last tick.
  std::optional<IntervalSample> close(uint64_t tick, uint64_t cumulative);
  void reset();

 private:
  IntervalSample take(uint64_t tick, uint64_t cumulative, bool last);
  uint32_t interval_;
  uint32_t ticks_ = 0;
  uint32_t delivered_ = 0;
  uint64_t in_avoidance_sum_ = 0;
  double throttle_sum_ = 0;
};

}  // namespace swarm_forage
