#pragma once
// The environmental condition (core/run/condition.hpp) in ROS form: environment/throttle, and the check
// that experiment files ask for (`run_experiment --conditions`).
#include <swarm_forage/Throttle.h>

#include <iosfwd>
#include <string>
#include <vector>

#include "swarm_forage/core/run/condition.hpp"

namespace swarm_forage {

/// The condition a throttle announces (Throttle.msg's `amplitude` is beta; "" waveform: null).
Condition conditionOf(const Throttle& t);
/// Writes `c` into a throttle's condition fields (not its tick, value or stamp).
void setCondition(Throttle& t, const Condition& c);

/// run_experiment --conditions [ticks:=T] [ticks_per_second:=F]: checks conditions exactly as a run's
/// start-up does (readCondition), for scripts/experiment.py, one call for a whole experiment file. Reads
/// one condition per line of `in` (tab-separated words, e.g. "waveform:=step_down\tbeta:=0.4") and writes
/// one line per condition: "ok\t<tag>" (Condition::tag), or "error\t<why>". Returns 0 when all are
/// valid, else 2.
int checkConditions(const std::vector<std::string>& run_words, std::istream& in, std::ostream& out);

}  // namespace swarm_forage
