// Periodic environment waveforms (sine, square, sawtooth) and their validation. The null, constant and
// step waveforms are covered in test_metrics.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "swarm_forage/core/run/waveform.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {
namespace {

constexpr double kPi = 3.14159265358979323846;

WaveformConfig periodic(const std::string& name, double amplitude, double frequency, double phase = 0,
                        double offset = 0) {
  WaveformConfig w;
  w.name = name;
  w.amplitude = amplitude;
  w.frequency = frequency;
  w.phase = phase;
  w.offset = offset;
  return w;
}

/// Runs validate(), which must throw ParameterError, and returns its message.
std::string validateError(const WaveformConfig& w) {
  try {
    w.validate();
  } catch (const ParameterError& e) {
    return e.what();
  }
  ADD_FAILURE() << "validate() accepted waveform " << w.name;
  return {};
}

TEST(PeriodicWaveform, SineAtChosenTimes) {
  // f = 0.125 Hz (period 8 s, exact in binary), amplitude 0.5, offset 0.2.
  const WaveformConfig w = periodic("sine", 0.5, 0.125, 0, 0.2);
  EXPECT_NEAR(waveformValue(w, 0), 0.2, 1e-12);                         // 0.2 + 0.5 sin(0)
  EXPECT_NEAR(waveformValue(w, 2), 0.7, 1e-12);                         // 0.2 + 0.5 sin(pi/2)
  EXPECT_NEAR(waveformValue(w, 4), 0.2, 1e-12);                         // 0.2 + 0.5 sin(pi)
  EXPECT_NEAR(waveformValue(w, 6), -0.3, 1e-12);                        // 0.2 + 0.5 sin(3 pi/2)
  EXPECT_NEAR(waveformValue(w, 1), 0.2 + 0.5 * std::sqrt(0.5), 1e-12);  // sin(pi/4) = sqrt(1/2)
  EXPECT_NEAR(waveformValue(w, 8000), 0.2, 1e-9);                       // 1000 whole periods
  // phase pi/2 turns sine into cosine: 0.2 + 0.5 cos(0) = 0.7 at t = 0, 0.2 + 0.5 cos(pi) = -0.3 at 4 s.
  const WaveformConfig c = periodic("sine", 0.5, 0.125, kPi / 2, 0.2);
  EXPECT_NEAR(waveformValue(c, 0), 0.7, 1e-12);
  EXPECT_NEAR(waveformValue(c, 4), -0.3, 1e-12);
  // A negative amplitude (a boost first) mirrors it: -0.4 sin(pi/2) = -0.4 at 2 s.
  EXPECT_NEAR(waveformValue(periodic("sine", -0.4, 0.125), 2), -0.4, 1e-12);
}

TEST(PeriodicWaveform, SquareWithSignOfZeroPositive) {
  const WaveformConfig w = periodic("square", 0.4, 0.125);  // period 8 s
  EXPECT_EQ(waveformValue(w, 0), 0.4);                      // sin(0) = 0 -> sign +1
  EXPECT_EQ(waveformValue(w, 1), 0.4);                      // sin(pi/4) > 0
  EXPECT_EQ(waveformValue(w, 4), 0.4);                      // sin(pi) = 0 -> +1
  EXPECT_EQ(waveformValue(w, 5), -0.4);                     // sin(5 pi/4) < 0
  EXPECT_EQ(waveformValue(w, 7.9), -0.4);
  EXPECT_EQ(waveformValue(w, 8), 0.4);    // sin(2 pi) = 0 -> +1
  EXPECT_EQ(waveformValue(w, 800), 0.4);  // sin(200 pi) = 0 -> +1
  // Phase pi shifts by half a period: t = 1 -> sin(5 pi/4) < 0; offset 0.5 adds.
  const WaveformConfig s = periodic("square", 0.4, 0.125, kPi, 0.5);
  EXPECT_DOUBLE_EQ(waveformValue(s, 1), 0.1);  // 0.5 - 0.4
  EXPECT_DOUBLE_EQ(waveformValue(s, 5), 0.9);  // 0.5 + 0.4 (sin(9 pi/4) > 0)
}

TEST(PeriodicWaveform, SawtoothRampsOverEachPeriod) {
  // offset 0.1 + 0.5 (2 frac(t/8) - 1)
  const WaveformConfig w = periodic("sawtooth", 0.5, 0.125, 0, 0.1);
  EXPECT_DOUBLE_EQ(waveformValue(w, 0), -0.4);      // frac 0: 0.1 + 0.5 (0 - 1)
  EXPECT_DOUBLE_EQ(waveformValue(w, 2), -0.15);     // frac 0.25: 0.1 + 0.5 (0.5 - 1)
  EXPECT_DOUBLE_EQ(waveformValue(w, 4), 0.1);       // frac 0.5: 0.1 + 0
  EXPECT_DOUBLE_EQ(waveformValue(w, 6), 0.35);      // frac 0.75: 0.1 + 0.5 (1.5 - 1)
  EXPECT_DOUBLE_EQ(waveformValue(w, 8), -0.4);      // next period starts again at the bottom
  EXPECT_NEAR(waveformValue(w, 7.999), 0.6, 1e-3);  // just before the drop: 0.1 + 0.5 (~2 - 1)
  // phase pi = half a cycle: frac(0 + 1/2) = 0.5 at t = 0.
  EXPECT_DOUBLE_EQ(waveformValue(periodic("sawtooth", 0.5, 0.125, kPi, 0.1), 0), 0.1);
}

TEST(PeriodicWaveform, ValidValuesStayWithinPlusMinusOne) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1), f(1e-4, 1e3), t(0, 1e4);
  for (const char* name : {"sine", "square", "sawtooth"}) {
    for (int k = 0; k < 200; ++k) {
      const double amplitude = u(rng), offset = (1 - std::fabs(amplitude)) * u(rng);
      const WaveformConfig w = periodic(name, amplitude, f(rng), 10 * u(rng), offset);
      ASSERT_NO_THROW(w.validate()) << name;
      for (int j = 0; j < 20; ++j) {
        const double v = waveformValue(w, t(rng));
        EXPECT_LE(std::fabs(v), 1.0 + 1e-12) << name;
      }
    }
  }
  // The extremes are allowed: |offset| + |amplitude| = 1 exactly.
  EXPECT_NO_THROW(periodic("sine", 0.5, 1, 0, -0.5).validate());
  EXPECT_NO_THROW(periodic("square", -1.0, 1e3).validate());
}

TEST(PeriodicWaveform, ValidateNamesFrequencyPhaseOffset) {
  EXPECT_EQ(validateError(periodic("sine", 0.5, 0)), "frequency must be in (0, 1000] Hz for sine (got 0)");
  EXPECT_EQ(validateError(periodic("square", 0.5, -1)),
            "frequency must be in (0, 1000] Hz for square (got -1)");
  EXPECT_EQ(validateError(periodic("sawtooth", 0.5, 1000.5)),
            "frequency must be in (0, 1000] Hz for sawtooth (got 1000.5)");
  EXPECT_NE(validateError(periodic("sine", 0.5, std::nan(""))).find("frequency"), std::string::npos);
  EXPECT_NE(validateError(periodic("sine", 0.5, std::numeric_limits<double>::infinity())).find("frequency"),
            std::string::npos);
  const std::string sum = validateError(periodic("sine", 0.5, 1, 0, 0.6));  // 0.6 + 0.5 = 1.1 > 1
  EXPECT_NE(sum.find("|offset| + |amplitude| must be <= 1 for sine"), std::string::npos) << sum;
  EXPECT_NE(sum.find("[-1, 1]"), std::string::npos) << sum;
  EXPECT_NE(validateError(periodic("sawtooth", -0.5, 1, 0, -0.6)).find("offset"), std::string::npos);
  EXPECT_NE(validateError(periodic("sine", 0.5, 1, std::nan(""))).find("phase"), std::string::npos);
  EXPECT_NE(
      validateError(periodic("sine", 0.1, 1, 0, std::numeric_limits<double>::infinity())).find("offset"),
      std::string::npos);
  EXPECT_NE(validateError(periodic("sine", 1.5, 1)).find("amplitude"), std::string::npos);
  // The periodic names are listed among the valid ones.
  const std::string unknown = validateError(periodic("triangle", 0.5, 1));
  for (const char* name : {"square", "sine", "sawtooth"})
    EXPECT_NE(unknown.find(name), std::string::npos) << unknown;
  EXPECT_TRUE(isPeriodicWaveform("sine") && isPeriodicWaveform("square") && isPeriodicWaveform("sawtooth"));
  EXPECT_FALSE(isPeriodicWaveform("step_up") || isPeriodicWaveform("null") || isPeriodicWaveform("constant"));
}

TEST(PeriodicWaveform, StepsIgnoreThePeriodicParameters) {
  // frequency 0 is fine for a step: it is not read; the value is the paper's V1 unchanged.
  WaveformConfig w = periodic("step_up", 0.8, 0, 1.0, 0.1);
  w.alpha = 10;
  EXPECT_NO_THROW(w.validate());
  EXPECT_EQ(waveformValue(w, 9), 0.0);
  EXPECT_DOUBLE_EQ(waveformValue(w, 10), 0.4);  // beta / 2 at t = alpha
  EXPECT_DOUBLE_EQ(waveformValue(w, 11), 0.8);
  w.name = "constant";
  EXPECT_EQ(waveformValue(w, 3), 0.8);
}

}  // namespace
}  // namespace swarm_forage
