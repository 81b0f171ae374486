#pragma once
// The environmental condition (core/run/condition.hpp) in ROS form: environment/throttle, and the check
// that experiment files ask for (`run_experiment --conditions`).
#include <swarm_forage/Throttle.h>

#include <iosfwd>
#include <string>
#include <vector>

#include "swarm_forage/core/run/condition.hpp"

namespace swarm_forage {

/// The condition in a message or config `m` whose fields are named as the condition's, beta as `beta`
/// ("" waveform: null; "" target: carry_speed, as in a throttle recorded before targets, LegacyThrottle).
template <typename M>
Condition conditionFrom(const M& m, double M::*beta) {
  Condition c;
  c.waveform = m.waveform.empty() ? "null" : m.waveform;
  c.beta = m.*beta;
  c.alpha = m.alpha;
  c.frequency = m.frequency;
  c.phase = m.phase;
  c.offset = m.offset;
  if (!m.target.empty()) c.target = m.target;
  c.series = m.series;
  return c;
}
/// Writes `c` into the condition fields of `m` (as conditionFrom reads them); returns `m`.
template <typename M>
M& assignCondition(M& m, const Condition& c, double M::*beta) {
  m.waveform = c.waveform;
  m.*beta = c.beta;
  m.alpha = c.alpha;
  m.frequency = c.frequency;
  m.phase = c.phase;
  m.offset = c.offset;
  m.target = c.target;
  m.series = c.series;
  return m;
}

/// The condition a throttle announces: Throttle.msg's `amplitude` is beta (renaming the field would
/// change the message's md5sum and make recorded bags unreadable).
inline Condition conditionOf(const Throttle& t) {
  Condition c = conditionFrom(t, &Throttle::amplitude);
  c.series_digest = t.series_digest;
  return c;
}
/// Writes `c` into a throttle's condition fields (not its tick, value or stamp).
inline void setCondition(Throttle& t, const Condition& c) {
  assignCondition(t, c, &Throttle::amplitude);
  t.series_digest = c.series_digest;
}

/// run_experiment --conditions [ticks:=T] [ticks_per_second:=F]: checks conditions exactly as a run's
/// start-up does (readCondition), for swarm_forage.experiment.file (src/swarm_forage/experiment/), one call for
/// a whole experiment file. Reads one condition per line of `in` (tab-separated words, e.g.
/// "waveform:=step_down\tbeta:=0.4") and writes one line per condition: "ok\t<tag>" (Condition::tag), or
/// "error\t<why>". Returns 0 when all are valid, else 2.
int checkConditions(const std::vector<std::string>& run_words, std::istream& in, std::ostream& out);

}  // namespace swarm_forage
