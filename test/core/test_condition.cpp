// Environmental conditions: the periodic waveforms (sine, square, sawtooth), validation, the run's
// resolution (forRun) and the tag. The null, constant and step waveforms are in test_metrics.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {
namespace {

constexpr double kPi = 3.14159265358979323846;

Condition periodic(const std::string& name, double beta, double frequency, double phase = 0,
                   double offset = 0) {
  Condition w;
  w.waveform = name;
  w.beta = beta;
  w.frequency = frequency;
  w.phase = phase;
  w.offset = offset;
  return w;
}

/// Runs validate(), which must throw ParameterError, and returns its message.
std::string validateError(const Condition& w) {
  try {
    w.validate();
  } catch (const ParameterError& e) {
    return e.what();
  }
  ADD_FAILURE() << "validate() accepted waveform " << w.waveform;
  return {};
}

TEST(PeriodicWaveform, SineAtChosenTimes) {
  // f = 0.125 Hz (period 8 s, exact in binary), beta 0.5, offset 0.2.
  const Condition w = periodic("sine", 0.5, 0.125, 0, 0.2);
  EXPECT_NEAR(w.value(0), 0.2, 1e-12);                         // 0.2 + 0.5 sin(0)
  EXPECT_NEAR(w.value(2), 0.7, 1e-12);                         // 0.2 + 0.5 sin(pi/2)
  EXPECT_NEAR(w.value(4), 0.2, 1e-12);                         // 0.2 + 0.5 sin(pi)
  EXPECT_NEAR(w.value(6), -0.3, 1e-12);                        // 0.2 + 0.5 sin(3 pi/2)
  EXPECT_NEAR(w.value(1), 0.2 + 0.5 * std::sqrt(0.5), 1e-12);  // sin(pi/4) = sqrt(1/2)
  EXPECT_NEAR(w.value(8000), 0.2, 1e-9);                       // 1000 whole periods
  // phase pi/2 turns sine into cosine: 0.2 + 0.5 cos(0) = 0.7 at t = 0, 0.2 + 0.5 cos(pi) = -0.3 at 4 s.
  const Condition c = periodic("sine", 0.5, 0.125, kPi / 2, 0.2);
  EXPECT_NEAR(c.value(0), 0.7, 1e-12);
  EXPECT_NEAR(c.value(4), -0.3, 1e-12);
  // A negative beta (a boost first) mirrors it: -0.4 sin(pi/2) = -0.4 at 2 s.
  EXPECT_NEAR(periodic("sine", -0.4, 0.125).value(2), -0.4, 1e-12);
}

TEST(PeriodicWaveform, SquareWithSignOfZeroPositive) {
  const Condition w = periodic("square", 0.4, 0.125);  // period 8 s
  EXPECT_EQ(w.value(0), 0.4);                          // sin(0) = 0 -> sign +1
  EXPECT_EQ(w.value(1), 0.4);                          // sin(pi/4) > 0
  EXPECT_EQ(w.value(4), 0.4);                          // sin(pi) = 0 -> +1
  EXPECT_EQ(w.value(5), -0.4);                         // sin(5 pi/4) < 0
  EXPECT_EQ(w.value(7.9), -0.4);
  EXPECT_EQ(w.value(8), 0.4);    // sin(2 pi) = 0 -> +1
  EXPECT_EQ(w.value(800), 0.4);  // sin(200 pi) = 0 -> +1
  // Phase pi shifts by half a period: t = 1 -> sin(5 pi/4) < 0; offset 0.5 adds.
  const Condition s = periodic("square", 0.4, 0.125, kPi, 0.5);
  EXPECT_DOUBLE_EQ(s.value(1), 0.1);  // 0.5 - 0.4
  EXPECT_DOUBLE_EQ(s.value(5), 0.9);  // 0.5 + 0.4 (sin(9 pi/4) > 0)
}

TEST(PeriodicWaveform, SawtoothRampsOverEachPeriod) {
  // offset 0.1 + 0.5 (2 frac(t/8) - 1)
  const Condition w = periodic("sawtooth", 0.5, 0.125, 0, 0.1);
  EXPECT_DOUBLE_EQ(w.value(0), -0.4);      // frac 0: 0.1 + 0.5 (0 - 1)
  EXPECT_DOUBLE_EQ(w.value(2), -0.15);     // frac 0.25: 0.1 + 0.5 (0.5 - 1)
  EXPECT_DOUBLE_EQ(w.value(4), 0.1);       // frac 0.5: 0.1 + 0
  EXPECT_DOUBLE_EQ(w.value(6), 0.35);      // frac 0.75: 0.1 + 0.5 (1.5 - 1)
  EXPECT_DOUBLE_EQ(w.value(8), -0.4);      // next period starts again at the bottom
  EXPECT_NEAR(w.value(7.999), 0.6, 1e-3);  // just before the drop: 0.1 + 0.5 (~2 - 1)
  // phase pi = half a cycle: frac(0 + 1/2) = 0.5 at t = 0.
  EXPECT_DOUBLE_EQ(periodic("sawtooth", 0.5, 0.125, kPi, 0.1).value(0), 0.1);
}

TEST(PeriodicWaveform, ValidValuesStayWithinPlusMinusOne) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1), f(1e-4, 1e3), t(0, 1e4);
  for (const char* name : {"sine", "square", "sawtooth"}) {
    for (int k = 0; k < 200; ++k) {
      const double beta = u(rng), offset = (1 - std::fabs(beta)) * u(rng);
      const Condition w = periodic(name, beta, f(rng), 10 * u(rng), offset);
      ASSERT_NO_THROW(w.validate()) << name;
      for (int j = 0; j < 20; ++j) {
        const double v = w.value(t(rng));
        EXPECT_LE(std::fabs(v), 1.0 + 1e-12) << name;
      }
    }
  }
  // The extremes are allowed: |offset| + |beta| = 1 exactly.
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
  EXPECT_NE(sum.find("|offset| + |beta| must be <= 1 for sine"), std::string::npos) << sum;
  EXPECT_NE(sum.find("[-1, 1]"), std::string::npos) << sum;
  EXPECT_NE(validateError(periodic("sawtooth", -0.5, 1, 0, -0.6)).find("offset"), std::string::npos);
  EXPECT_NE(validateError(periodic("sine", 0.5, 1, std::nan(""))).find("phase"), std::string::npos);
  EXPECT_NE(
      validateError(periodic("sine", 0.1, 1, 0, std::numeric_limits<double>::infinity())).find("offset"),
      std::string::npos);
  EXPECT_NE(validateError(periodic("sine", 1.5, 1)).find("beta"), std::string::npos);
  // The periodic names are listed among the valid ones.
  const std::string unknown = validateError(periodic("triangle", 0.5, 1));
  for (const char* name : {"square", "sine", "sawtooth"})
    EXPECT_NE(unknown.find(name), std::string::npos) << unknown;
  EXPECT_TRUE(isPeriodicWaveform("sine") && isPeriodicWaveform("square") && isPeriodicWaveform("sawtooth"));
  EXPECT_FALSE(isPeriodicWaveform("step_up") || isPeriodicWaveform("null") || isPeriodicWaveform("constant"));
}

TEST(PeriodicWaveform, StepsIgnoreThePeriodicParameters) {
  // frequency 0 is fine for a step: it is not read; the value is the paper's V1 unchanged.
  Condition w = periodic("step_up", 0.8, 0, 1.0, 0.1);
  w.alpha = 10;
  EXPECT_NO_THROW(w.validate());
  EXPECT_EQ(w.value(9), 0.0);
  EXPECT_DOUBLE_EQ(w.value(10), 0.4);  // beta / 2 at t = alpha
  EXPECT_DOUBLE_EQ(w.value(11), 0.8);
  w.waveform = "constant";
  EXPECT_EQ(w.value(3), 0.8);
}

Condition step(const std::string& name, double beta, double alpha) {
  Condition c;
  c.waveform = name;
  c.beta = beta;
  c.alpha = alpha;
  return c;
}

std::string forRunError(const Condition& c, uint64_t ticks, double tps) {
  try {
    c.forRun(ticks, tps);
  } catch (const ParameterError& e) {
    return e.what();
  }
  ADD_FAILURE() << "forRun accepted " << c.label();
  return {};
}

TEST(Condition, ForRunResolvesAlphaAndKeepsStepsWithinTheRun) {
  // alpha -1 (the parameters' default): half the run, 50,000 ticks at 5 ticks/s = 10,000 s.
  EXPECT_EQ(step("step_down", 0.4, -1).forRun(50000, 5.0).alpha, 5000.0);
  EXPECT_EQ(step("step_down", 0.4, 2000).forRun(50000, 5.0).alpha, 2000.0);
  const std::string late = forRunError(step("step_up", 0.4, 20000), 50000, 5.0);
  EXPECT_NE(late.find("alpha 20000 s is not within the run"), std::string::npos) << late;
  EXPECT_NE(late.find("10000 s"), std::string::npos) << late;
  EXPECT_NE(forRunError(step("step_up", 0.4, -5), 50000, 5.0).find("or -1 for half the run"),
            std::string::npos);
  // The same rule as validate(): beta in [-1, 1].
  EXPECT_NE(forRunError(step("constant", 1.5, 0), 100, 5.0).find("beta must be in [-1, 1]"),
            std::string::npos);
  // alpha is not read by a constant: any finite time is fine.
  EXPECT_NO_THROW(step("constant", 0.3, 1e6).forRun(100, 5.0));
}

TEST(Condition, TagIsTheFileNameAndSweepKeyLabel) {
  // What swarm_forage.experiment's record keys have always held ('%s%g'): keys must not change.
  EXPECT_EQ(step("step_down", 0.4, 0).tag(), "step_down0.4");
  EXPECT_EQ(step("square", -0.4, 0).tag(), "square-0.4");
  EXPECT_EQ(step("constant", 0, 0).tag(), "constant0");
  EXPECT_EQ(step("constant", 0.1234567, 0).tag(), "constant0.123457");
  EXPECT_EQ(Condition{}.tag(), "null");
  // Bag names tag the normalized condition: any ideal one is null.
  EXPECT_EQ(step("constant", 0, 0).normalized().tag(), "null");
}

TEST(Condition, NormalizedClearsWhatTheWaveformDoesNotRead) {
  Condition c = periodic("sine", 0.2, 0.001, 1.0, 0.1);
  c.alpha = 300;
  EXPECT_EQ(c.normalized().alpha, 0.0);
  EXPECT_EQ(c.normalized().frequency, 0.001);
  Condition s = step("step_up", 0.3, 100);
  s.frequency = 5;
  EXPECT_EQ(s.normalized(), step("step_up", 0.3, 100));
  EXPECT_EQ(step("step_up", 0, 100).normalized(), Condition{});
}

TEST(Condition, ParametersAreListedOnce) {
  std::vector<std::string> names;
  for (const ConditionParameter& p : conditionParameters()) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"waveform", "beta", "alpha", "frequency", "phase", "offset",
                                             "target", "series"}));
}

}  // namespace
}  // namespace swarm_forage
