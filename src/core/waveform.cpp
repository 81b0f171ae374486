#include "swarm_forage/core/waveform.hpp"

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/config.hpp"

namespace swarm_forage {

const std::vector<std::string>& waveformNames() {
  static const std::vector<std::string> names = {"null", "constant", "step_up", "step_down"};
  return names;
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
  if (!(alpha >= 0.0) || !std::isfinite(alpha))
    throw ParameterError("alpha must be a finite time >= 0 s (got " + std::to_string(alpha) + ")");
}

double waveformValue(const WaveformConfig& w, double t) {
  if (w.name == "constant") return w.amplitude;
  if (w.name == "step_up" || w.name == "step_down") {
    // The paper's Heaviside step V1 = beta * H(t - alpha) with H(0) = 1/2; V2 = beta - V1.
    const double v1 = t < w.alpha ? 0.0 : (t == w.alpha ? w.amplitude / 2 : w.amplitude);
    return w.name == "step_up" ? v1 : w.amplitude - v1;
  }
  return 0.0;
}

}  // namespace swarm_forage
