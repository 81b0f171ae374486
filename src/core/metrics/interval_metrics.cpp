#include "swarm_forage/core/metrics/interval_metrics.hpp"

#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

void writeSampleRow(std::ostream& out, uint32_t run, uint32_t swarm_size, const IntervalSample& s) {
  out << run << ',' << swarm_size << ',' << s.tick_end << ',' << s.interval_ticks << ',' << s.cumulative
      << ',' << s.delivered << ',' << s.mean_in_avoidance << ',' << s.speed << ',' << (s.final ? 1 : 0)
      << '\n';
}

IntervalAccumulator::IntervalAccumulator(uint32_t interval_ticks) : interval_(interval_ticks) {
  if (interval_ticks < 1) throw ParameterError("sample_interval must be >= 1 tick (got 0)");
}

void IntervalAccumulator::reset() {
  ticks_ = 0;
  delivered_ = 0;
  in_avoidance_sum_ = 0;
  throttle_sum_ = 0;
}

std::optional<IntervalSample> IntervalAccumulator::add(uint64_t tick, uint32_t delivered, uint64_t cumulative,
                                                       uint32_t in_avoidance, bool last, double throttle) {
  ++ticks_;
  delivered_ += delivered;
  in_avoidance_sum_ += in_avoidance;
  throttle_sum_ += throttle;
  if (ticks_ < interval_ && !last) return std::nullopt;
  return take(tick, cumulative, last);
}

std::optional<IntervalSample> IntervalAccumulator::close(uint64_t tick, uint64_t cumulative) {
  if (ticks_ == 0) return std::nullopt;
  return take(tick, cumulative, false);
}

IntervalSample IntervalAccumulator::take(uint64_t tick, uint64_t cumulative, bool last) {
  IntervalSample s;
  s.tick_end = tick;
  s.interval_ticks = ticks_;
  s.cumulative = cumulative;
  s.delivered = delivered_;
  s.mean_in_avoidance = static_cast<double>(in_avoidance_sum_) / ticks_;
  s.speed = 1.0 - throttle_sum_ / ticks_;
  s.final = last;
  reset();
  return s;
}

}  // namespace swarm_forage
