#pragma once
// The environmental condition of a run (docs/design-model.md, Environmental condition): a waveform V(t) and
// its target, what V acts on: by default robots carrying a block, effective speed = commanded x (1 - V(t)); a
// negative V is a boost (core/world/throttling.hpp has the targets).
// The one form of a condition: start-up parameters, dynamic_reconfigure, experiment files (through
// `run_experiment --conditions`), environment/throttle and the run library all convert to and from it.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/run/condition_series.hpp"
#include "swarm_forage/core/world/throttling.hpp"

namespace swarm_forage {

/// Which fields a waveform reads:
///   null       V = 0
///   constant   V = beta
///   step_up    V = 0 for t < alpha, beta/2 at t = alpha, beta for t > alpha (paper's V1)
///   step_down  V = beta - step_up (paper's V2)
///   sine       V = offset + beta * sin(2 pi f t + phase)
///   square     V = offset + beta * sign(sin(2 pi f t + phase)), sign(0) = +1
///   sawtooth   V = offset + beta * (2 frac(f t + phase / (2 pi)) - 1), frac(x) = x - floor(x)
///   series     V = the file `series` at t (ConditionSeries), read by forRun; beta and the rest unread
/// Fields a waveform does not read are ignored (but must still be finite where validate() says so).
/// Every waveform has a target (targetNames()); carry_speed is the paper's and the default.
struct Condition {
  std::string waveform = "null";       // one of waveformNames()
  double beta = 0.0;                   // amplitude, in [-1, 1]
  double alpha = 0.0;                  // step time [s]
  double frequency = 0.0;              // f [Hz], sine / square / sawtooth
  double phase = 0.0;                  // [rad], sine / square / sawtooth
  double offset = 0.0;                 // sine / square / sawtooth
  std::string target = "carry_speed";  // one of targetNames()
  std::string series;                  // series: the file (as resolved; not part of the identity)
  std::string series_digest;           // series: ConditionSeries::digest of its bytes (part of the identity)
  std::shared_ptr<const ConditionSeries> points;  // series: the rows, once forRun has read the file

  /// V(t) for t in seconds. The periodic waveforms are evaluated on the cycle fraction
  /// u = frac(f t + phase / (2 pi)) (sin(2 pi f t + phase) = sin(2 pi u)), so a zero crossing that
  /// falls on an exact number of cycles gives exactly sign(0) = +1 for square.
  double value(double t) const;

  /// Throws ParameterError naming the parameter and its valid range:
  ///   waveform in waveformNames(); beta in [-1, 1], and 0 for null; alpha finite and >= 0; phase and
  ///   offset finite; for sine, square and sawtooth: frequency in (0, 1000] Hz and |offset| + |beta| <= 1,
  ///   so that V(t) stays within [-1, 1] for every t (it reaches offset +- |beta|).
  void validate() const;
  /// The condition as a run of `ticks` at `ticks_per_second` applies it: alpha < 0 (-1 as given) becomes
  /// half the run; a step must fall within the run; a series reads its file (points, series_digest); then
  /// validate(). Throws ParameterError (a malformed file: naming the file and the line).
  Condition forRun(uint64_t ticks, double ticks_per_second) const;

  /// What the world applies at a tick of value `v`: V and the target.
  Throttling throttling(double v) const;

  /// V = 0 throughout: null, or a waveform of zero beta (and zero offset where it reads one); never series.
  bool ideal() const;
  /// One form for every way of writing the same condition: any ideal one is null (target carry_speed),
  /// and the fields its waveform does not read are 0 or "" (what the run library groups and identities
  /// compare). A series keeps its file's name and digest; the digest alone tells series apart.
  Condition normalized() const;
  /// What a reader sees: "null", "step_down beta=0.4 alpha=5000s",
  /// "sine beta=0.2 f=0.001Hz phase=0 offset=0" (the fields the waveform reads),
  /// "series profile.csv #1a2b3c4d" (the digest's first 8 digits); " target=speed" when not carry_speed.
  std::string label() const;
  /// The label in a file name or sweep record key: "null", or the waveform and beta, "step_down0.4",
  /// "series-1a2b3c4d"; "-speed" or "-manipulation_time" appended when the target is not carry_speed.
  std::string tag() const;

  bool operator<(const Condition& o) const;
  bool operator==(const Condition& o) const { return !(*this < o) && !(o < *this); }
};

/// null, constant, step_up, step_down, square, sine, sawtooth, series.
const std::vector<std::string>& waveformNames();
/// carry_speed, speed, manipulation_time (ConditionTarget, in that order).
const std::vector<std::string>& targetNames();
/// True for sine, square and sawtooth.
bool isPeriodicWaveform(const std::string& name);
/// True for step_up and step_down.
bool isStepWaveform(const std::string& name);

/// A condition's parameters as a user sets them (node ~parameters, run_experiment words, experiment
/// files; cfg/Environment.cfg repeats them for dynamic_reconfigure) and what each accepts (--help).
struct ConditionParameter {
  std::string name, valid;
};
const std::vector<ConditionParameter>& conditionParameters();

}  // namespace swarm_forage
