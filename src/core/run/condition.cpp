#include "swarm_forage/core/run/condition.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <tuple>

#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

namespace {
constexpr double kTwoPi = 6.283185307179586476925286766559;
constexpr double kMaxFrequency = 1e3;  // [Hz]

/// "%g": labels, file names and sweep keys have always written numbers so (keys must not change).
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

/// Fraction of the current cycle, in [0, 1).
double cycleFraction(const Condition& c, double t) {
  const double x = c.frequency * t + c.phase / kTwoPi;
  const double u = x - std::floor(x);
  return u < 1.0 ? u : 0.0;  // x slightly below an integer can round up to 1
}
}  // namespace

const std::vector<std::string>& waveformNames() {
  static const std::vector<std::string> names = {"null",   "constant", "step_up",  "step_down",
                                                 "square", "sine",     "sawtooth", "series"};
  return names;
}

const std::vector<std::string>& targetNames() {
  static const std::vector<std::string> names = {"carry_speed", "speed", "manipulation_time"};
  return names;
}

bool isPeriodicWaveform(const std::string& name) {
  return name == "sine" || name == "square" || name == "sawtooth";
}

bool isStepWaveform(const std::string& name) { return name == "step_up" || name == "step_down"; }

const std::vector<ConditionParameter>& conditionParameters() {
  static const std::vector<ConditionParameter> params = {
      {"waveform", "one of " + joined(waveformNames())},
      {"beta", "a number in [-1, 1] (negative boosts); 0 for null"},
      {"alpha", "step time, a number >= 0 s within the run, or -1 for half the run"},
      {"frequency", "a number in (0, 1000] Hz (sine, square, sawtooth)"},
      {"phase", "a number, rad (sine, square, sawtooth)"},
      {"offset", "a number, |offset| + |beta| <= 1 (sine, square, sawtooth)"},
      {"target", "one of " + joined(targetNames()) + " (what V acts on)"},
      {"series", "a CSV file of rows t [s], V (series): a path, or a file name of config/conditions"}};
  return params;
}

void Condition::validate() const {
  const auto& names = waveformNames();
  if (std::find(names.begin(), names.end(), waveform) == names.end())
    throw ParameterError("waveform '" + waveform + "' is not valid; valid: " + joined(names));
  if (!(beta >= -1.0 && beta <= 1.0))
    throw ParameterError("beta must be in [-1, 1] (negative boosts; got " + num(beta) + ")");
  // One rule at start-up and live: a null run with a beta would be labelled ideal yet look configured.
  if (waveform == "null" && beta != 0.0)
    throw ParameterError("beta has no effect on waveform null (V = 0; got beta " + num(beta) +
                         "): set a waveform too, e.g. constant, or beta 0");
  if (!(alpha >= 0.0) || !std::isfinite(alpha))
    throw ParameterError("alpha must be a time >= 0 s, or -1 for half the run (got " + num(alpha) + ")");
  if (!std::isfinite(phase))
    throw ParameterError("phase must be a finite angle in rad (got " + num(phase) + ")");
  if (!std::isfinite(offset)) throw ParameterError("offset must be finite (got " + num(offset) + ")");
  const auto& targets = targetNames();
  if (std::find(targets.begin(), targets.end(), target) == targets.end())
    throw ParameterError("target '" + target + "' is not valid; valid: " + joined(targets));
  if (waveform == "series" && (series.empty() || series_digest.empty()))
    throw ParameterError("series must name a CSV file of rows t [s], V for waveform series (got '" + series +
                         "')");
  if (!isPeriodicWaveform(waveform)) return;
  if (!(frequency > 0.0 && frequency <= kMaxFrequency))
    throw ParameterError("frequency must be in (0, 1000] Hz for " + waveform + " (got " + num(frequency) +
                         ")");
  if (std::fabs(offset) + std::fabs(beta) > 1.0)
    throw ParameterError("|offset| + |beta| must be <= 1 for " + waveform +
                         " so that V(t) stays within [-1, 1] (got |" + num(offset) + "| + |" + num(beta) +
                         "| = " + num(std::fabs(offset) + std::fabs(beta)) + ")");
}

Condition Condition::forRun(uint64_t ticks, double ticks_per_second) const {
  Condition c = *this;
  if (c.waveform == "series" && !c.series.empty()) {  // a malformed file is refused here, before tick 0
    c.points = ConditionSeries::read(c.series);
    c.series_digest = c.points->digest;
  }
  const double run_seconds = static_cast<double>(ticks) / ticks_per_second;
  if (c.alpha < 0 && c.alpha >= -1.0) c.alpha = run_seconds / 2;  // the paper's choice
  c.validate();
  // A step at or after the run's end never happens: the run would be labelled step_up yet be ideal.
  if (isStepWaveform(c.waveform) && c.alpha >= run_seconds) {
    std::ostringstream msg;
    msg << "alpha " << c.alpha << " s is not within the run (ticks " << ticks << " at " << ticks_per_second
        << " ticks/s = " << run_seconds << " s): the " << c.waveform << " would never happen; valid: [0, "
        << run_seconds << ") s, or -1 for half the run";
    throw ParameterError(msg.str());
  }
  return c;
}

double Condition::value(double t) const {
  if (waveform == "constant") return beta;
  if (isStepWaveform(waveform)) {
    // The paper's Heaviside step V1 = beta * H(t - alpha) with H(0) = 1/2; V2 = beta - V1.
    const double v1 = t < alpha ? 0.0 : (t == alpha ? beta / 2 : beta);
    return waveform == "step_up" ? v1 : beta - v1;
  }
  if (waveform == "sine") return offset + beta * std::sin(kTwoPi * cycleFraction(*this, t));
  // sin(2 pi u) >= 0 exactly for u in [0, 1/2]; sign(0) = +1.
  if (waveform == "square") return offset + (cycleFraction(*this, t) <= 0.5 ? beta : -beta);
  if (waveform == "sawtooth") return offset + beta * (2.0 * cycleFraction(*this, t) - 1.0);
  if (waveform == "series" && points) return points->at(t);
  return 0.0;
}

Throttling Condition::throttling(double v) const {
  const auto& targets = targetNames();
  const auto k = std::find(targets.begin(), targets.end(), target) - targets.begin();
  return {v, k < static_cast<long>(targets.size()) ? static_cast<ConditionTarget>(k)
                                                   : ConditionTarget::kCarrySpeed};
}

bool Condition::ideal() const {
  if (waveform == "null") return true;
  if (waveform == "series") return false;
  return beta == 0 && (offset == 0 || !isPeriodicWaveform(waveform));
}

Condition Condition::normalized() const {
  if (ideal()) return {};
  Condition c = *this;
  if (!isStepWaveform(c.waveform)) c.alpha = 0;
  if (!isPeriodicWaveform(c.waveform)) c.frequency = c.phase = c.offset = 0;
  if (c.waveform == "series") {
    c.beta = 0;
  } else {
    c.series.clear();
    c.series_digest.clear();
    c.points.reset();
  }
  return c;
}

std::string Condition::label() const {
  if (ideal()) return "null";
  const std::string on = target == "carry_speed" ? "" : " target=" + target;
  if (waveform == "series")
    return "series " + series.substr(series.rfind('/') + 1) + " #" + series_digest.substr(0, 8) + on;
  std::string s = waveform + " beta=" + num(beta);
  if (isStepWaveform(waveform)) s += " alpha=" + num(alpha) + "s";
  if (isPeriodicWaveform(waveform))
    s += " f=" + num(frequency) + "Hz phase=" + num(phase) + " offset=" + num(offset);
  return s + on;
}

std::string Condition::tag() const {
  if (waveform == "null") return "null";
  const std::string head =
      waveform == "series" ? "series-" + series_digest.substr(0, 8) : waveform + num(beta);
  return target == "carry_speed" ? head : head + "-" + target;
}

// The series' name is not compared: the same rows under another path are the same condition.
bool Condition::operator<(const Condition& o) const {
  return std::tie(waveform, beta, alpha, frequency, phase, offset, target, series_digest) <
         std::tie(o.waveform, o.beta, o.alpha, o.frequency, o.phase, o.offset, o.target, o.series_digest);
}

}  // namespace swarm_forage
