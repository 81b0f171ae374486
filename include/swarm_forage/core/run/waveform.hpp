#pragma once
// Environmental-condition waveforms V(t) (DESIGN section 4, Environment). V(t) throttles the speed of
// robots carrying a block: effective speed = commanded x (1 - V(t)); a negative V is a boost.
#include <string>
#include <vector>

namespace swarm_forage {

/// Parameters of one waveform. Which fields a waveform reads:
///   null       V = 0
///   constant   V = amplitude
///   step_up    V = 0 for t < alpha, amplitude/2 at t = alpha, amplitude for t > alpha (paper's V1)
///   step_down  V = amplitude - step_up (paper's V2)
///   sine       V = offset + amplitude * sin(2 pi f t + phase)
///   square     V = offset + amplitude * sign(sin(2 pi f t + phase)), sign(0) = +1
///   sawtooth   V = offset + amplitude * (2 frac(f t + phase / (2 pi)) - 1), frac(x) = x - floor(x)
/// Fields a waveform does not read are ignored (but must still be finite where validate() says so).
struct WaveformConfig {
  std::string name = "null";  // one of waveformNames()
  double amplitude = 0.0;     // beta
  double alpha = 0.0;         // step time [s]
  double frequency = 0.0;     // f [Hz], sine / square / sawtooth
  double phase = 0.0;         // [rad], sine / square / sawtooth
  double offset = 0.0;        // sine / square / sawtooth

  /// Throws ParameterError naming the parameter and its valid range:
  ///   name in waveformNames(); amplitude in [-1, 1]; alpha finite and >= 0; phase and offset finite;
  ///   for sine, square and sawtooth: frequency in (0, 1000] Hz and |offset| + |amplitude| <= 1, so
  ///   that V(t) stays within [-1, 1] for every t (it reaches offset +- |amplitude|).
  void validate() const;
};

/// null, constant, step_up, step_down, square, sine, sawtooth.
const std::vector<std::string>& waveformNames();

/// True for sine, square and sawtooth.
bool isPeriodicWaveform(const std::string& name);

/// V(t) for t in seconds. The periodic waveforms are evaluated on the cycle fraction
/// u = frac(f t + phase / (2 pi)) (sin(2 pi f t + phase) = sin(2 pi u)), so a zero crossing that
/// falls on an exact number of cycles gives exactly sign(0) = +1 for square.
double waveformValue(const WaveformConfig& w, double t);

}  // namespace swarm_forage
