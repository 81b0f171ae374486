#pragma once
// Environmental-condition waveforms V(t) (DESIGN section 4, Environment).
#include <string>
#include <vector>

namespace swarm_forage {

struct WaveformConfig {
  std::string name = "null";  // null, constant, step_up, step_down
  double amplitude = 0.0;     // beta
  double alpha = 0.0;         // step time [s]
  double frequency = 0.0;     // [Hz] (periodic waveforms, later)
  double phase = 0.0;         // [rad]
  double offset = 0.0;

  void validate() const;  // throws ParameterError
};

const std::vector<std::string>& waveformNames();

/// V(t) for t in seconds.
double waveformValue(const WaveformConfig& w, double t);

}  // namespace swarm_forage
