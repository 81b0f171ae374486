// The run library (grouping, references) and evaluateRun / metricTables on hand-computed cases, plus
// the speed condition s(t) of the interval sampler. The arithmetic is beside each number.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/interval_metrics.hpp"
#include "swarm_forage/core/metrics/run_library.hpp"
#include "swarm_forage/core/metrics/swarm_metrics.hpp"

namespace swarm_forage {
namespace {

using V = std::vector<double>;
constexpr auto kPaper = Definitions::kPaper;

RunSeries series(uint32_t n, V P, V p, V n_ca, V s, uint32_t interval = 1000) {
  return RunSeries{n, interval, std::move(P), std::move(p), std::move(n_ca), std::move(s)};
}
Condition env(const std::string& waveform, double beta = 0, double alpha = 0, double frequency = 0,
              double offset = 0) {
  Condition c;
  c.waveform = waveform;
  c.beta = beta;
  c.alpha = alpha;
  c.frequency = frequency;
  c.offset = offset;
  return c;
}
RunKey key(uint32_t n, Condition e = {}, const std::string& controller = "crw",
           const std::string& arena = "32x16") {
  return RunKey{controller, arena, n, std::move(e), {}};
}
RunRecord record(const RunKey& k, uint32_t seed, const RunSeries& s) { return RunRecord{k, seed, "test", s}; }
/// A single-sample run of N robots delivering P blocks.
RunRecord simple(const RunKey& k, uint32_t seed, double P) {
  return record(k, seed, series(k.swarm_size, {P}, {P}, {0}, {1}));
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The hand-computed case: crw in 32x16, ideal, 4 samples.
//   N = 1: P_lost(1) = p n_ca = {2.5, 0, 0, 5}
//   N = 2: P_lost(2) = p n_ca / 2 - 2 P_lost(1) = {4 - 5, 12, 10, 5 - 10} = {-1, 12, 10, -5}
//   N = 4: P_lost(4) = p n_ca / 4 - 4 P_lost(1) = {6 - 10, 20, 13, 7.5 - 20} = {-4, 20, 13, -12.5}
//   theta(4) = P_lost(4) - (4/2) P_lost(2) = {-2, -4, -7, -2.5}
const RunSeries kOne = series(1, {10, 25, 40, 50}, {10, 15, 15, 10}, {0.25, 0, 0, 0.5}, {1, 1, 1, 1});
const RunSeries kTwo = series(2, {16, 40, 60, 80}, {16, 24, 20, 20}, {0.5, 1, 1, 0.5}, {1, 1, 1, 1});
const RunSeries kFour = series(4, {24, 64, 90, 120}, {24, 40, 26, 30}, {1, 2, 2, 1}, {1, 1, 1, 1});
// step_down beta 0.5: V = 0.5 until alpha, then 0, so s = {0.5, 0.5, 1, 1}.
const Condition kStep = env("step_down", 0.5, 2000);
const RunSeries kFourStep = series(4, {12, 32, 58, 88}, {12, 20, 26, 30}, {1, 1, 2, 1}, {0.5, 0.5, 1, 1});

/// Z = sum_t [1 - 1/(1 + e^-theta)] = sum_t 1/(1 + e^theta).
double zSum(const V& theta) {
  double z = 0;
  for (double t : theta) z += 1.0 / (1.0 + std::exp(t));
  return z;
}

RunLibrary handLibrary() {
  RunLibrary lib;
  lib.add(record(key(1), 1, kOne));
  lib.add(record(key(2), 1, kTwo));
  lib.add(record(key(4), 1, kFour));
  lib.add(record(key(4, kStep), 1, kFourStep));
  return lib;
}

void expectFinite(const RunEvaluation& ev) {
  for (double v :
       {ev.scalability.phi.value, ev.scalability.e.value, ev.self_organization.z_sum.value,
        ev.self_organization.z_mean.value, ev.reactivity.distance.value, ev.adaptability.distance.value})
    EXPECT_TRUE(std::isfinite(v));
  for (const MetricSeries* s : {&ev.scalability.phi_t, &ev.scalability.e_t, &ev.self_organization.theta})
    for (double v : s->value) EXPECT_TRUE(std::isfinite(v));
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string f; std::getline(in, f, sep);) out.push_back(f);
  return out;
}

/// The fields of the row of `table` that starts with `prefix` (the CSV's quoted fields hold no commas
/// here: the labels and "ok"); empty when there is none.
std::vector<std::string> row(const std::string& table, const std::string& prefix) {
  for (const std::string& line : split(table, '\n'))
    if (line.rfind(prefix, 0) == 0) return split(line, ',');
  return {};
}

TEST(RunSeriesSpeed, AccumulatorSpeedIsOneMinusMeanThrottle) {
  IntervalAccumulator acc(4);
  const V throttle = {0.25, 0.5, 0.75, 0.5, -0.5, -0.25};
  std::vector<IntervalSample> samples;
  for (uint64_t t = 0; t < throttle.size(); ++t)
    if (auto s = acc.add(t, 0, 0, 0, t + 1 == throttle.size(), throttle[t])) samples.push_back(*s);
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_DOUBLE_EQ(samples[0].speed, 0.5);  // 1 - (0.25 + 0.5 + 0.75 + 0.5) / 4
  EXPECT_EQ(samples[1].interval_ticks, 2u);
  EXPECT_TRUE(samples[1].final);
  EXPECT_DOUBLE_EQ(samples[1].speed, 1.375);  // boost: 1 - (-0.5 - 0.25) / 2

  IntervalAccumulator plain(2);  // throttle defaults to 0: s = 1
  EXPECT_FALSE(plain.add(0, 1, 1, 0, false));
  const auto s = plain.add(1, 1, 2, 0, false);
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(s->speed, 1.0);
}

TEST(RunSeriesBuilder, BuildsEveryFieldAndFinishesOnTheLastTick) {
  RunSeriesBuilder b(2, 3);
  // tick:                              0  1    2    3    4 (last)
  const std::vector<uint32_t> delivered = {1, 0, 2, 1, 3};
  const std::vector<uint32_t> avoiding = {1, 2, 0, 3, 2};
  const V throttle = {0, 0.5, 0.5, 0.5, -0.5};
  uint64_t cumulative = 0;
  for (uint64_t t = 0; t < delivered.size(); ++t) {
    cumulative += delivered[t];
    const bool last = t + 1 == delivered.size();
    EXPECT_FALSE(b.finished());
    const auto s = b.add(t, delivered[t], cumulative, avoiding[t], last, throttle[t]);
    EXPECT_EQ(s.has_value(), t == 1 || t == 3 || t == 4) << "tick " << t;
  }
  EXPECT_TRUE(b.finished());
  const RunSeries& r = b.series();
  EXPECT_EQ(r.swarm_size, 3u);
  EXPECT_EQ(r.interval, 2u);
  EXPECT_EQ(r.P, (V{1, 4, 7}));
  EXPECT_EQ(r.p, (V{1, 3, 3}));
  EXPECT_EQ(r.n_ca, (V{1.5, 1.5, 2}));  // (1 + 2) / 2, (0 + 3) / 2, 2 / 1
  EXPECT_EQ(r.s, (V{0.75, 0.5, 1.5}));  // 1 - 0.5 / 2, 1 - 1 / 2, 1 - (-0.5)
}

TEST(Condition, IdealAndLabel) {
  EXPECT_TRUE(Condition{}.ideal());
  EXPECT_TRUE(env("null", 0.7).ideal());
  EXPECT_TRUE(env("constant", 0).ideal());
  EXPECT_TRUE(env("step_down", 0, 5000).ideal());
  EXPECT_TRUE(env("sine", 0, 0, 0.001).ideal());
  EXPECT_FALSE(env("sine", 0, 0, 0.001, 0.2).ideal());  // V = offset = 0.2 throughout
  EXPECT_FALSE(env("constant", 0.3).ideal());
  EXPECT_FALSE(env("step_up", 0.4, 5000).ideal());

  EXPECT_EQ(Condition{}.label(), "null");
  EXPECT_EQ(env("constant", 0).label(), "null");
  EXPECT_EQ(env("step_down", 0.4, 5000).label(), "step_down beta=0.4 alpha=5000s");
  EXPECT_EQ(env("sine", 0.2, 0, 0.001).label(), "sine beta=0.2 f=0.001Hz phase=0 offset=0");
  EXPECT_EQ(env("sine", 0, 0, 0.001, 0.2).label(), "sine beta=0 f=0.001Hz phase=0 offset=0.2");
  EXPECT_EQ(env("constant", 0.3).label(), "constant beta=0.3");
  EXPECT_EQ(key(16).label(), "crw 32x16 N=16 null");
}

TEST(Condition, LibraryGroupsEquivalentEnvironments) {
  RunLibrary lib;
  lib.add(simple(key(4, env("constant", 0)), 1, 10));
  lib.add(simple(key(4), 2, 20));
  lib.add(simple(key(4, env("step_down", 0, 3000)), 3, 30));
  lib.add(simple(key(4, env("sine", 0, 0, 0.001, 0.2)), 4, 40));  // not ideal: its own group
  // Fields a waveform does not read do not split groups.
  lib.add(simple(key(4, env("sine", 0, 99, 0.001, 0.2)), 5, 50));
  EXPECT_EQ(lib.size(), 5u);
  ASSERT_EQ(lib.groups().size(), 2u);
  const AggregatedRuns& ideal = lib.groups().at(key(4));
  EXPECT_EQ(ideal.runs, 3u);
  EXPECT_EQ(ideal.mean.P, (V{20}));  // (10 + 20 + 30) / 3
  EXPECT_EQ(lib.runs(key(4, env("step_up", 0))).size(), 3u);
  EXPECT_EQ(lib.runs(key(4, env("sine", 0, 0, 0.001, 0.2))).size(), 2u);
}

TEST(RunLibrary, CopiesShareTheRunsUntilOneAdds) {
  // resampled() shares the runs with its library rather than copying them; an add to either copies first.
  RunLibrary lib;
  lib.add(record(key(2), 1, series(2, {10}, {10}, {0}, {1})));
  lib.add(record(key(2), 2, series(2, {30}, {30}, {0}, {1})));
  const RunLibrary draw = lib.resampled(1, 1);
  EXPECT_EQ(draw.size(), 2u);
  EXPECT_EQ(draw.runs(key(2)), lib.runs(key(2)));  // the same records, not copies
  RunLibrary copy = lib;
  copy.add(record(key(2), 3, series(2, {50}, {50}, {0}, {1})));
  EXPECT_EQ(copy.size(), 3u);
  EXPECT_EQ(lib.size(), 2u);
  EXPECT_EQ(lib.groups().at(key(2)).mean.P, (V{20}));
  EXPECT_EQ(copy.groups().at(key(2)).mean.P, (V{30}));
  EXPECT_EQ(draw.runs(key(2)).size(), 2u);
}

TEST(RunLibrary, SameSeedReplacesAndGroupsHoldTheMean) {
  RunLibrary lib;
  lib.add(record(key(2), 5, series(2, {10, 30}, {10, 20}, {1, 0}, {1, 0.5})));
  lib.add(record(key(2), 2, series(2, {20, 50}, {20, 30}, {0, 2}, {1, 1.5})));
  EXPECT_EQ(lib.size(), 2u);
  const AggregatedRuns* g = &lib.groups().at(key(2));
  EXPECT_EQ(g->runs, 2u);
  EXPECT_EQ(g->mean.P, (V{15, 40}));
  EXPECT_EQ(g->mean.p, (V{15, 25}));
  EXPECT_EQ(g->mean.n_ca, (V{0.5, 1}));
  EXPECT_EQ(g->mean.s, (V{1, 1}));
  const auto runs = lib.runs(key(2));
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0]->seed, 2u);  // seed order
  EXPECT_EQ(runs[1]->seed, 5u);

  lib.add(record(key(2), 5, series(2, {40, 70}, {40, 30}, {1, 0}, {1, 0.5})));  // replaces seed 5
  EXPECT_EQ(lib.size(), 2u);
  g = &lib.groups().at(key(2));
  EXPECT_EQ(g->runs, 2u);
  EXPECT_EQ(g->mean.P, (V{30, 60}));  // (20 + 40) / 2, (50 + 70) / 2
}

TEST(RunLibrary, SmallerSingleAndIdealReferences) {
  RunLibrary lib;
  lib.add(simple(key(2), 1, 2));
  lib.add(simple(key(4), 1, 4));
  lib.add(simple(key(6, {}, "dpo"), 1, 6));           // other controller
  lib.add(simple(key(6, {}, "crw", "64x64"), 1, 6));  // other arena
  lib.add(simple(key(6, kStep), 1, 6));               // other environment
  lib.add(simple(key(8, kStep), 1, 8));

  const Reference prev = lib.smaller(key(8));
  ASSERT_TRUE(prev.runs) << prev.missing;
  EXPECT_EQ(prev.runs->mean.swarm_size, 4u);
  EXPECT_TRUE(prev.missing.empty());
  const Reference prev_step = lib.smaller(key(8, kStep));
  ASSERT_TRUE(prev_step.runs) << prev_step.missing;
  EXPECT_EQ(prev_step.runs->mean.P, (V{6}));

  const Reference none = lib.smaller(key(2));
  EXPECT_FALSE(none.runs);
  EXPECT_TRUE(contains(none.missing, "N < 2")) << none.missing;
  EXPECT_TRUE(contains(none.missing, "crw")) << none.missing;

  const Reference ideal = lib.ideal(key(8, kStep));
  EXPECT_FALSE(ideal.runs);
  EXPECT_TRUE(contains(ideal.missing, "crw")) << ideal.missing;
  EXPECT_TRUE(contains(ideal.missing, "N = 8")) << ideal.missing;
  EXPECT_TRUE(contains(ideal.missing, "[crw 32x16 N=8 step_down beta=0.5 alpha=2000s]")) << ideal.missing;
  const Reference ideal4 = lib.ideal(key(4, kStep));
  ASSERT_TRUE(ideal4.runs) << ideal4.missing;
  EXPECT_EQ(ideal4.runs->mean.P, (V{4}));
  const Reference ideal6 = lib.ideal(key(6, kStep));  // not dpo's nor 64x64's: those are listed
  EXPECT_FALSE(ideal6.runs);
  EXPECT_TRUE(contains(ideal6.missing, "[crw 64x64 N=6 null] [dpo 32x16 N=6 null]")) << ideal6.missing;

  const Reference single = lib.single(key(8));
  EXPECT_FALSE(single.runs);
  EXPECT_TRUE(contains(single.missing, "N = 1")) << single.missing;
  lib.add(simple(key(1, env("constant", 0)), 1, 1));
  ASSERT_TRUE(lib.single(key(8)).runs);
  EXPECT_EQ(lib.single(key(8)).runs->mean.P, (V{1}));
}

TEST(RunLibrary, MissingReferenceNamesWhatIsMissingAndWhatIsThere) {
  RunLibrary lib;
  lib.add(simple(key(8, {}, "dpo"), 1, 8));
  lib.add(simple(key(16), 1, 16));
  const Reference prev = lib.smaller(key(8));
  EXPECT_FALSE(prev.runs);
  EXPECT_TRUE(contains(prev.missing, "N < 8")) << prev.missing;
  EXPECT_TRUE(contains(prev.missing, "crw")) << prev.missing;
  EXPECT_TRUE(contains(prev.missing, "32x16")) << prev.missing;
  const Reference ideal = lib.ideal(key(8, kStep));
  EXPECT_FALSE(ideal.runs);
  EXPECT_TRUE(contains(ideal.missing, "crw")) << ideal.missing;
  EXPECT_TRUE(contains(ideal.missing, "[dpo 32x16 N=8 null]")) << ideal.missing;
  EXPECT_FALSE(contains(ideal.missing, "N=16")) << ideal.missing;

  // A group whose runs cannot be combined is named with the reason.
  lib.add(record(key(8), 1, series(8, {1}, {1}, {0}, {1}, 1000)));
  lib.add(record(key(8), 2, series(8, {1}, {1}, {0}, {1}, 500)));
  const Reference bad = lib.ideal(key(8, kStep));
  EXPECT_FALSE(bad.runs);
  EXPECT_TRUE(contains(bad.missing, "cannot be used")) << bad.missing;
  EXPECT_TRUE(contains(bad.missing, "sample interval")) << bad.missing;
}

TEST(Evaluate, ScalabilityAndSelfOrganizationByHand) {
  const RunLibrary lib = handLibrary();
  const RunEvaluation four = evaluateRun(lib, key(4), kFour, true, kPaper);
  expectFinite(four);
  ASSERT_TRUE(four.scalability_status.valid) << four.scalability_status.status;
  EXPECT_EQ(four.scalability_status.status, "ok");
  EXPECT_EQ(four.scalability_status.reference_size, 2u);
  EXPECT_EQ(four.scalability.n_used, 2u);
  // phi = P(4) / ((4/2) P(2)) = 120 / 160 = 0.75; e = (1/0.75 - 1/2) / (1 - 1/2) = 5/3
  EXPECT_DOUBLE_EQ(four.scalability.phi.value, 0.75);
  EXPECT_DOUBLE_EQ(four.scalability.e.value, 5.0 / 3.0);
  ASSERT_TRUE(four.self_organization_status.valid) << four.self_organization_status.status;
  EXPECT_EQ(four.self_organization_status.status, "ok");
  EXPECT_EQ(four.self_organization_status.reference_size, 2u);
  EXPECT_NEAR(four.self_organization.z_sum.value, zSum({-2, -4, -7, -2.5}), 1e-12);
  EXPECT_NEAR(four.self_organization.z_mean.value, zSum({-2, -4, -7, -2.5}) / 4, 1e-12);
  EXPECT_FALSE(four.reactivity_status.valid);
  EXPECT_TRUE(contains(four.reactivity_status.status, "ideal")) << four.reactivity_status.status;
  EXPECT_FALSE(four.adaptability_status.valid);
  EXPECT_TRUE(contains(four.adaptability_status.status, "ideal")) << four.adaptability_status.status;

  // N = 2 against N = 1: phi = 80 / (2 * 50) = 0.8; N1 = 1, so e uses N2: (1.25 - 0.5) / 0.5 = 1.5
  const RunEvaluation two = evaluateRun(lib, key(2), kTwo, true, kPaper);
  ASSERT_TRUE(two.scalability_status.valid) << two.scalability_status.status;
  EXPECT_EQ(two.scalability_status.reference_size, 1u);
  EXPECT_DOUBLE_EQ(two.scalability.e.value, 1.5);
  EXPECT_TRUE(two.self_organization_status.valid) << two.self_organization_status.status;
  EXPECT_EQ(two.self_organization_status.reference_size, 1u);

  const RunEvaluation one = evaluateRun(lib, key(1), kOne, true, kPaper);
  expectFinite(one);
  EXPECT_FALSE(one.scalability_status.valid);
  EXPECT_FALSE(one.self_organization_status.valid);
  EXPECT_TRUE(contains(one.scalability_status.status, "N = 1")) << one.scalability_status.status;

  // Without an N = 1 group Z is still valid: P_lost(1, t) cancels from theta (m_prev > 1); the status says
  // so.
  RunLibrary no_single;
  no_single.add(record(key(2), 1, kTwo));
  const RunEvaluation z0 = evaluateRun(no_single, key(4), kFour, true, kPaper);
  ASSERT_TRUE(z0.self_organization_status.valid) << z0.self_organization_status.status;
  EXPECT_TRUE(contains(z0.self_organization_status.status, "ok, but")) << z0.self_organization_status.status;
  EXPECT_NEAR(z0.self_organization.z_sum.value, zSum({-2, -4, -7, -2.5}), 1e-12);
}

TEST(Evaluate, MissingReferenceIsInvalidNeverNaN) {
  RunLibrary lib;
  lib.add(simple(key(8, {}, "dpo"), 1, 8));
  const RunSeries run = series(8, {24, 64}, {24, 40}, {1, 2}, {0.5, 1}, 1000);
  for (const RunKey& k : {key(8), key(8, kStep)}) {
    const RunEvaluation ev = evaluateRun(lib, k, run, true, kPaper);
    expectFinite(ev);
    EXPECT_FALSE(ev.scalability_status.valid);
    EXPECT_FALSE(ev.self_organization_status.valid);
    EXPECT_TRUE(contains(ev.scalability_status.status, "N < 8")) << ev.scalability_status.status;
    EXPECT_FALSE(ev.reactivity_status.valid);
    EXPECT_FALSE(ev.adaptability_status.valid);
    EXPECT_FALSE(ev.reactivity_status.status.empty());
    EXPECT_NE(ev.reactivity_status.status, "ok");
  }
  const RunEvaluation step = evaluateRun(lib, key(8, kStep), run, true, kPaper);
  EXPECT_TRUE(contains(step.reactivity_status.status, "[dpo 32x16 N=8 null]"))
      << step.reactivity_status.status;
}

TEST(Evaluate, LiveRunUsesTheCutReferencesFinalRunTheWholeOnes) {
  const RunLibrary lib = handLibrary();
  const RunSeries live = series(4, {24, 64}, {24, 40}, {1, 2}, {1, 1});  // first 2 samples of kFour
  const RunEvaluation ev = evaluateRun(lib, key(4), live, false, kPaper);
  expectFinite(ev);
  ASSERT_TRUE(ev.scalability_status.valid) << ev.scalability_status.status;
  // phi = 64 / (2 * 40) = 0.8; e = (1.25 - 0.5) / 0.5 = 1.5
  EXPECT_DOUBLE_EQ(ev.scalability.phi.value, 0.8);
  EXPECT_DOUBLE_EQ(ev.scalability.e.value, 1.5);
  EXPECT_EQ(ev.scalability.e_t.value.size(), 2u);
  ASSERT_TRUE(ev.self_organization_status.valid) << ev.self_organization_status.status;
  EXPECT_NEAR(ev.self_organization.z_sum.value, zSum({-2, -4}), 1e-12);

  const RunEvaluation fin = evaluateRun(lib, key(4), live, true, kPaper);
  expectFinite(fin);
  EXPECT_FALSE(fin.scalability_status.valid);
  EXPECT_TRUE(contains(fin.scalability_status.status, "4 samples")) << fin.scalability_status.status;
  EXPECT_FALSE(fin.self_organization_status.valid);
  EXPECT_FALSE(fin.self_organization_status.status.empty());

  const RunSeries live_step = series(4, {12, 32}, {12, 20}, {1, 1}, {0.5, 0.5});
  EXPECT_TRUE(evaluateRun(lib, key(4, kStep), live_step, false, kPaper).reactivity_status.valid);
  const RunEvaluation fin_step = evaluateRun(lib, key(4, kStep), live_step, true, kPaper);
  EXPECT_FALSE(fin_step.reactivity_status.valid);
  EXPECT_FALSE(fin_step.adaptability_status.valid);
  EXPECT_TRUE(contains(fin_step.reactivity_status.status, "4 samples")) << fin_step.reactivity_status.status;
}

TEST(Evaluate, ReactivityAndAdaptabilityAgainstTheIdealGroup) {
  const RunLibrary lib = handLibrary();
  const RunEvaluation ev = evaluateRun(lib, key(4, kStep), kFourStep, true, kPaper);
  expectFinite(ev);
  ASSERT_TRUE(ev.reactivity_status.valid) << ev.reactivity_status.status;
  ASSERT_TRUE(ev.adaptability_status.valid) << ev.adaptability_status.status;
  EXPECT_EQ(ev.reactivity_status.reference_size, 4u);
  // P_R* = Q(s, min P_ideal = 24, max = 40) = {24, 24, 40, 40}; DTW to p = {12, 20, 26, 30}:
  // path (0,0) 12, (1,1) 4, (1,2) 2, (2,3) 10, (3,3) 10 = 38
  EXPECT_EQ(ev.reactivity.ideal, (V{24, 24, 40, 40}));
  EXPECT_DOUBLE_EQ(ev.reactivity.distance.value, 38);
  // P_A* = p_ideal (s <= 1) = {24, 40, 26, 30}; path (0,0) 12, (0,1) 4, (1,2) 14, (2,2) 0, (3,3) 0 = 30
  EXPECT_EQ(ev.adaptability.ideal, (V{24, 40, 26, 30}));
  EXPECT_DOUBLE_EQ(ev.adaptability.distance.value, 30);
  // No smaller step_down run: e and Z are invalid with the reason.
  EXPECT_FALSE(ev.scalability_status.valid);
  EXPECT_TRUE(contains(ev.scalability_status.status, "N < 4")) << ev.scalability_status.status;
}

TEST(MetricTables, RowsProblemsAndFullPrecision) {
  RunLibrary lib = handLibrary();
  lib.add(simple(key(8, {}, "dpo"), 1, 8));  // no smaller dpo run
  const MetricTables t = metricTables(lib, kPaper);

  const auto sc = split(t.scalability, '\n'), so = split(t.self_organization, '\n'),
             fx = split(t.flexibility, '\n');
  ASSERT_FALSE(sc.empty());
  const std::string tail = ",sample_interval,identity";
  EXPECT_EQ(sc[0], "controller,arena,waveform,beta,environment,N1,N2,N_used,runs,phi,e,valid,status" + tail);
  EXPECT_EQ(
      so[0],
      "controller,arena,waveform,beta,environment,m_prev,m_i,runs,theta_Z,Z_sum,Z_mean,valid,status" + tail);
  EXPECT_EQ(fx[0], "controller,arena,waveform,beta,environment,N,runs,R,A,valid,status" + tail);
  // Groups with N > 1: crw null N = 2, 4; crw step_down N = 4; dpo null N = 8.
  EXPECT_EQ(sc.size(), 5u);
  EXPECT_EQ(so.size(), 5u);
  EXPECT_EQ(fx.size(), 2u);  // the step_down group only

  const RunEvaluation four = evaluateRun(lib, key(4), kFour, true, kPaper);
  const auto e = row(t.scalability, "crw,32x16,null,0,\"null\",2,4,");
  ASSERT_EQ(e.size(), 15u) << t.scalability;
  EXPECT_EQ(e[7], "2");  // N_used
  EXPECT_EQ(e[8], "1");  // runs
  EXPECT_EQ(std::stod(e[9]), four.scalability.phi.value);
  EXPECT_EQ(std::stod(e[10]), four.scalability.e.value);  // 5/3 to all 17 digits
  EXPECT_EQ(e[11] + e[12], "1\"ok\"");
  const auto z = row(t.self_organization, "crw,32x16,null,0,\"null\",2,4,");
  ASSERT_EQ(z.size(), 15u) << t.self_organization;
  EXPECT_EQ(std::stod(z[8]), -2.5);  // theta_Z at the last sample
  EXPECT_EQ(std::stod(z[9]), four.self_organization.z_sum.value);
  EXPECT_EQ(std::stod(z[10]), four.self_organization.z_mean.value);
  EXPECT_EQ(z[11], "1");
  const auto f = row(t.flexibility, "crw,32x16,step_down,0.5,\"step_down beta=0.5 alpha=2000s\",4,1,");
  ASSERT_EQ(f.size(), 13u) << t.flexibility;
  EXPECT_EQ(std::stod(f[7]), 38.0);
  EXPECT_EQ(std::stod(f[8]), 30.0);
  EXPECT_EQ(f[9], "1");

  // Problems: e and Z of the step_down group (no smaller step_down run) and of dpo N = 8.
  auto named = [&](const std::string& who, const std::string& metric) {
    for (const std::string& p : t.problems)
      if (p.rfind(who + ": " + metric + ": ", 0) == 0) return true;
    return false;
  };
  EXPECT_TRUE(named("dpo 32x16 N=8 null", "e"));
  EXPECT_TRUE(named("dpo 32x16 N=8 null", "Z"));
  EXPECT_TRUE(named("crw 32x16 N=4 step_down beta=0.5 alpha=2000s", "e"));
  EXPECT_FALSE(named("crw 32x16 N=4 null", "e"));
  EXPECT_FALSE(named("crw 32x16 N=4 step_down beta=0.5 alpha=2000s", "R"));
  EXPECT_EQ(t.problems.size(), 4u);
  for (const std::string& p : t.problems) EXPECT_FALSE(contains(p, "N=2 null: ")) << p;
}

}  // namespace
}  // namespace swarm_forage

namespace swarm_forage {
namespace {

TEST(MetricTables, SeriesTickEndIsTheLastTickOfTheSample) {
  // As in metrics/performance and the live CSV: sample k of interval 1000 ends at tick 1000 (k + 1) - 1;
  // series.csv said 1000 (k + 1).
  RunLibrary lib;
  lib.add(record(key(1), 1, kOne));
  lib.add(record(key(1), 2, kOne));
  const std::vector<std::string> lines = split(groupSeriesCsv(lib), '\n');
  ASSERT_EQ(lines.size(), 5u);  // the header and 4 samples
  const std::vector<std::string> header = split(lines[0], ',');
  const std::size_t column = std::find(header.begin(), header.end(), "tick_end") - header.begin();
  ASSERT_LT(column, header.size());
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_EQ(split(lines[k + 1], ',')[column], std::to_string(1000 * (k + 1) - 1)) << lines[k + 1];
}

TEST(RunIdentity, EverySettingThatChangesTheOutcomeTellsRunsApart) {
  const RunKey base = key(8, env("step_up", 0.4, 5000));
  std::vector<RunKey> variants(9, base);
  variants[0].environment.alpha = 2500;  // alpha alone
  variants[1].setup.arena_width = 33;    // same arena name, other geometry
  variants[2].setup.n_blocks = 51;
  variants[3].setup.ticks = 1;
  variants[4].setup.controller_constants = "crw/wander_force=8";
  variants[5].setup.world_constants = "robot/radius=0.1";
  variants[6].setup.mode = "realtime";
  variants[7].setup.ticks_per_second = 10;
  variants[8].swarm_size = 16;
  for (const RunKey& v : variants) {
    EXPECT_NE(v.identity(), base.identity()) << v.describe();
    EXPECT_TRUE(v < base || base < v);
  }
  // Fields a waveform does not read are not part of it; the sample interval groups but names no bag.
  RunKey same = base;
  same.environment.frequency = 7;
  RunKey other_interval = base;
  other_interval.setup.interval = 500;
  EXPECT_EQ(same.identity(), base.identity());
  EXPECT_EQ(other_interval.identity(), base.identity());
  EXPECT_NE(other_interval.describe(), base.describe());

  RunLibrary lib;
  lib.add(simple(base, 1, 5));
  lib.add(simple(variants[1], 1, 5));
  lib.add(simple(other_interval, 1, 5));
  EXPECT_EQ(lib.groups().size(), 3u) << "two arenas named 32x16 must not merge";
}

TEST(RunIdentity, ReferencesShareTheWholeSetup) {
  RunLibrary lib;
  RunKey four = key(4), eight = key(8);
  four.setup.ticks = 1000;
  eight.setup.ticks = 2000;  // a longer run is no reference for e
  lib.add(simple(four, 1, 5));
  EXPECT_EQ(lib.smaller(eight).runs, nullptr);
  four.setup.ticks = 2000;
  lib.add(simple(four, 1, 5));
  EXPECT_NE(lib.smaller(eight).runs, nullptr);
}

TEST(RunLibrary, DuplicatesAreReportedNeverDroppedSilently) {
  RunLibrary lib;
  RunRecord a = simple(key(4), 3, 10), b = simple(key(4), 3, 10), c = simple(key(4), 3, 11);
  a.source = "lib/a.bag";
  b.source = "lib/b.bag";  // a copy: identical series
  c.source = "lib/c.bag";  // same identity and seed, other result (e.g. a realtime run)
  EXPECT_TRUE(lib.add(a).problem.empty());
  const AddResult copy = lib.add(b), differs = lib.add(c);
  EXPECT_FALSE(copy.added);
  EXPECT_TRUE(contains(copy.problem, "lib/b.bag: the same run")) << copy.problem;
  EXPECT_TRUE(contains(copy.problem, "as lib/a.bag, which is the one used (identical series)"))
      << copy.problem;
  EXPECT_TRUE(contains(differs.problem, "(their series differ)")) << differs.problem;
  EXPECT_EQ(lib.size(), 1u);
  EXPECT_EQ(lib.groups().at(key(4)).mean.P, (V{10}));

  // Re-reading a source replaces it; a live run and its own bag are one run, the bag is kept.
  a.series.P = {12};
  EXPECT_TRUE(lib.add(a).added);
  EXPECT_EQ(lib.groups().at(key(4)).mean.P, (V{12}));
  RunRecord live = simple(key(8), 1, 4), bag = simple(key(8), 1, 4);
  live.source = "live run 0";
  bag.source = "lib/run8.bag";
  EXPECT_TRUE(lib.add(live).problem.empty());
  const AddResult own = lib.add(bag);
  EXPECT_TRUE(own.added && own.problem.empty());
  EXPECT_EQ(lib.runs(key(8)).front()->source, "lib/run8.bag");
  const AddResult again = lib.add(live);
  EXPECT_TRUE(!again.added && again.problem.empty());
}

TEST(RunLibrary, RecordsOfDifferentModelVersionsAreNeverGrouped) {
  RunLibrary lib;
  RunRecord a = simple(key(4), 1, 10), b = simple(key(4), 2, 20), live = simple(key(4), 3, 30);
  a.source = "lib/a.bag";
  a.model_version = 7;
  b.source = "lib/b.bag";
  b.model_version = 6;         // the same identity, made by an older model
  live.source = "live run 0";  // no provenance: not known, never refused for it
  EXPECT_TRUE(lib.add(a).added);
  const AddResult older = lib.add(b);
  EXPECT_FALSE(older.added);
  EXPECT_TRUE(contains(older.problem, "lib/b.bag: made by model version 6, but lib/a.bag")) << older.problem;
  EXPECT_TRUE(
      contains(older.problem, "by model version 7: records of different model versions are never grouped"))
      << older.problem;
  EXPECT_EQ(lib.groups().at(key(4)).mean.P, (V{10}));
  EXPECT_TRUE(lib.add(live).added);
  b.model_version = 7;
  EXPECT_TRUE(lib.add(b).added);
  EXPECT_EQ(lib.runs(key(4)).size(), 3u);
}

}  // namespace
}  // namespace swarm_forage
