#include "swarm_forage/core/run/waveform.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

namespace {
constexpr double kTwoPi = 6.283185307179586476925286766559;
constexpr double kMaxFrequency = 1e3;  // [Hz]

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// Fraction of the current cycle, in [0, 1).
double cycleFraction(const WaveformConfig& w, double t) {
  const double x = w.frequency * t + w.phase / kTwoPi;
  const double u = x - std::floor(x);
  return u < 1.0 ? u : 0.0;  // x slightly below an integer can round up to 1
}
}  // namespace

const std::vector<std::string>& waveformNames() {
  static const std::vector<std::string> names = {"null",   "constant", "step_up", "step_down",
                                                 "square", "sine",     "sawtooth"};
  return names;
}

bool isPeriodicWaveform(const std::string& name) {
  return name == "sine" || name == "square" || name == "sawtooth";
}

void WaveformConfig::validate() const {
  const auto& names = waveformNames();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string valid;
    for (const auto& n : names) valid += (valid.empty() ? "" : ", ") + n;
    throw ParameterError("waveform '" + name + "' is unknown; valid: " + valid);
  }
  if (!(amplitude >= -1.0 && amplitude <= 1.0))
    throw ParameterError("beta (amplitude) must be in [-1, 1] (negative boosts; got " +
                         std::to_string(amplitude) + ")");
  // One rule at start-up and live: a null run with a beta would be labelled ideal yet look configured.
  if (name == "null" && amplitude != 0.0)
    throw ParameterError("beta has no effect on waveform null (V = 0; got beta " + num(amplitude) +
                         "): set a waveform too, e.g. constant, or beta 0");
  if (!(alpha >= 0.0) || !std::isfinite(alpha))
    throw ParameterError("alpha must be a finite time >= 0 s (got " + std::to_string(alpha) + ")");
  if (!std::isfinite(phase))
    throw ParameterError("phase must be a finite angle in rad (got " + num(phase) + ")");
  if (!std::isfinite(offset)) throw ParameterError("offset must be finite (got " + num(offset) + ")");
  if (!isPeriodicWaveform(name)) return;
  if (!(frequency > 0.0 && frequency <= kMaxFrequency))
    throw ParameterError("frequency must be in (0, 1000] Hz for " + name + " (got " + num(frequency) + ")");
  if (std::fabs(offset) + std::fabs(amplitude) > 1.0)
    throw ParameterError("|offset| + |amplitude| must be <= 1 for " + name +
                         " so that V(t) stays within [-1, 1] (got |" + num(offset) + "| + |" +
                         num(amplitude) + "| = " + num(std::fabs(offset) + std::fabs(amplitude)) + ")");
}

double waveformValue(const WaveformConfig& w, double t) {
  if (w.name == "constant") return w.amplitude;
  if (w.name == "step_up" || w.name == "step_down") {
    // The paper's Heaviside step V1 = beta * H(t - alpha) with H(0) = 1/2; V2 = beta - V1.
    const double v1 = t < w.alpha ? 0.0 : (t == w.alpha ? w.amplitude / 2 : w.amplitude);
    return w.name == "step_up" ? v1 : w.amplitude - v1;
  }
  if (w.name == "sine") return w.offset + w.amplitude * std::sin(kTwoPi * cycleFraction(w, t));
  // sin(2 pi u) >= 0 exactly for u in [0, 1/2]; sign(0) = +1.
  if (w.name == "square") return w.offset + (cycleFraction(w, t) <= 0.5 ? w.amplitude : -w.amplitude);
  if (w.name == "sawtooth") return w.offset + w.amplitude * (2.0 * cycleFraction(w, t) - 1.0);
  return 0.0;
}

}  // namespace swarm_forage
