// Swarm metrics (docs/design-model.md, Metrics) against hand-computed cases; the arithmetic is beside each
// number.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/swarm_metrics.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {
namespace {

using V = std::vector<double>;
constexpr auto kAuthors = Definitions::kAuthorsCode2019;

RunSeries run(uint32_t n, V P, V p = {}, V n_ca = {}, V s = {}, uint32_t interval = 1000) {
  RunSeries r;
  r.swarm_size = n;
  r.interval = interval;
  r.P = std::move(P);
  r.p = std::move(p);
  r.n_ca = std::move(n_ca);
  r.s = std::move(s);
  return r;
}

void expectFinite(const MetricValue& v) {
  EXPECT_TRUE(std::isfinite(v.value)) << v.reason;
  EXPECT_EQ(v.valid, v.reason.empty()) << v.reason;
}
void expectFinite(const MetricSeries& s) {
  ASSERT_EQ(s.value.size(), s.sample_valid.size());
  for (double v : s.value) EXPECT_TRUE(std::isfinite(v));
  EXPECT_EQ(s.valid, s.reason.empty()) << s.reason;
}
void expectFinite(const Scalability& s) {
  for (const auto* v : {&s.phi, &s.e}) expectFinite(*v);
  for (const auto* v : {&s.phi_t, &s.e_t}) expectFinite(*v);
}
void expectFinite(const SelfOrganization& s) {
  for (const auto* v : {&s.z_sum, &s.z_mean}) expectFinite(*v);
  for (const auto* v : {&s.p_lost_prev, &s.p_lost_cur, &s.theta}) expectFinite(*v);
}
void expectFinite(const Flexibility& f) {
  expectFinite(f.distance);
  for (double v : f.ideal) EXPECT_TRUE(std::isfinite(v));
}

TEST(Definitions, ParsesTheFourNamesAndRejectsOthers) {
  EXPECT_EQ(parseDefinitions("paper"), Definitions::kPaper);
  EXPECT_EQ(parseDefinitions("authors_code_2019"), kAuthors);
  EXPECT_EQ(parseDefinitions("authors_code_2020"), Definitions::kAuthorsCode2020);
  EXPECT_EQ(parseDefinitions("authors_code"), Definitions::kAuthorsCode);
  for (const std::string& name : definitionsNames()) EXPECT_EQ(definitionsName(parseDefinitions(name)), name);
  EXPECT_TRUE(authors2019Rules(Definitions::kAuthorsCode));  // e, Z, R, A as the 2019 scripts
  EXPECT_TRUE(authors2019Rules(Definitions::kAuthorsCode2020));
  EXPECT_FALSE(authors2019Rules(Definitions::kPaper));
  try {
    parseDefinitions("authors");
    FAIL() << "accepted";
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()),
              "definitions must be one of: paper, authors_code_2019, authors_code_2020, authors_code (got "
              "'authors')");
  }
}

TEST(Scalability, KarpFlattForN1TwoN2Four) {
  // P(2,t) = [4, 10], P(4,t) = [8, 15].
  const Scalability s = scalability(run(2, {4, 10}), run(4, {8, 15}));
  expectFinite(s);
  EXPECT_EQ(s.n_used, 2u);
  EXPECT_TRUE(s.note.empty());
  ASSERT_TRUE(s.phi.valid && s.e.valid && s.phi_t.valid && s.e_t.valid);
  EXPECT_DOUBLE_EQ(s.phi.value, 0.75);      // 15 / ((4/2) 10) = 15/20
  EXPECT_DOUBLE_EQ(s.e.value, 5.0 / 3.0);   // (1/0.75 - 1/2) / (1 - 1/2) = (4/3 - 1/2) / (1/2) = 5/3
  EXPECT_DOUBLE_EQ(s.phi_t.value[0], 1.0);  // 8 / (2 * 4)
  EXPECT_DOUBLE_EQ(s.e_t.value[0], 1.0);    // (1 - 1/2) / (1/2)
  EXPECT_DOUBLE_EQ(s.e_t.value[1], s.e.value);
  // authors_code_2019 takes N2 = 4 in e: (4/3 - 1/4) / (1 - 1/4) = (13/12) / (3/4) = 13/9; phi unchanged.
  const Scalability a = scalability(run(2, {4, 10}), run(4, {8, 15}), kAuthors);
  EXPECT_EQ(a.n_used, 4u);
  EXPECT_DOUBLE_EQ(a.phi.value, 0.75);
  EXPECT_DOUBLE_EQ(a.e.value, 13.0 / 9.0);
  EXPECT_DOUBLE_EQ(a.e_t.value[0], 1.0);  // phi = 1: (1 - 1/4) / (3/4) = 1 in both modes
  EXPECT_NE(a.note.find("N2"), std::string::npos);
  // The scalar helpers.
  EXPECT_DOUBLE_EQ(karpFlattPhi(10, 15, 2, 4).value, 0.75);
  EXPECT_DOUBLE_EQ(karpFlattE(0.5, 4).value, 7.0 / 3.0);  // (2 - 1/4) / (3/4) = 7/3
}

TEST(Scalability, N1OfOneUsesN2) {
  // P(1,T) = 10, P(2,T) = 16: phi = 16 / ((2/1) 10) = 0.8; e with N2 = 2: (1.25 - 0.5) / 0.5 = 1.5.
  const Scalability s = scalability(run(1, {5, 10}), run(2, {8, 16}));
  expectFinite(s);
  EXPECT_EQ(s.n_used, 2u);
  EXPECT_NE(s.note.find("N1 = 1"), std::string::npos) << s.note;
  EXPECT_DOUBLE_EQ(s.phi.value, 0.8);
  EXPECT_DOUBLE_EQ(s.e.value, 1.5);
  EXPECT_DOUBLE_EQ(s.e_t.value[0], 1.5);  // 8 / (2 * 5) = 0.8 again
  const Scalability a = scalability(run(1, {5, 10}), run(2, {8, 16}), kAuthors);
  EXPECT_EQ(a.e.value, s.e.value);  // both modes use N2 here
  // The paper's formula itself is 0/0 at N = 1.
  EXPECT_FALSE(karpFlattE(0.8, 1).valid);
  EXPECT_NE(karpFlattE(0.8, 1).reason.find("0/0"), std::string::npos);
}

TEST(Scalability, TimeResolvedSeriesWithAZeroSample) {
  // P(2,t) = [0, 4, 10], P(4,t) = [2, 8, 15]: sample 0 has P(N1) = 0.
  const Scalability s = scalability(run(2, {0, 4, 10}), run(4, {2, 8, 15}));
  expectFinite(s);
  EXPECT_EQ(s.e_t.sample_valid, std::vector<bool>({false, true, true}));
  EXPECT_EQ(s.e_t.value, V({0.0, 1.0, s.e.value}));  // invalid -> 0; 8/(2*4) = 1 -> e = 1; 5/3
  EXPECT_FALSE(s.e_t.valid);
  EXPECT_EQ(s.e_t.reason, "P(N1) is 0 at 1 of 3 samples");
  EXPECT_TRUE(s.e.valid);  // the final value is fine
  EXPECT_DOUBLE_EQ(s.e.value, 5.0 / 3.0);
}

TEST(Scalability, ZeroPerformanceEmptyAndMismatchedRunsAreDefined) {
  const Scalability zero = scalability(run(2, {0, 0}), run(4, {0, 0}));
  expectFinite(zero);
  EXPECT_FALSE(zero.e.valid);
  EXPECT_EQ(zero.e_t.reason, "P(N1) is 0 at every sample");
  EXPECT_EQ(zero.e.reason, "P(N1) is 0 at T");
  // P(N2,T) = 0 < P(N1,T): phi = 0 is valid, e = (1/0 - ...) is unbounded -> invalid.
  const Scalability stalled = scalability(run(2, {3}), run(4, {0}));
  expectFinite(stalled);
  EXPECT_TRUE(stalled.phi.valid);
  EXPECT_EQ(stalled.phi.value, 0.0);
  EXPECT_FALSE(stalled.e.valid);
  EXPECT_NE(stalled.e.reason.find("unbounded"), std::string::npos);
  const Scalability empty = scalability(run(2, {}), run(4, {}));
  expectFinite(empty);
  EXPECT_EQ(empty.e.reason, "no samples");
  const Scalability mismatch = scalability(run(2, {1, 2, 3}), run(4, {1, 2, 3, 4, 5}));
  expectFinite(mismatch);
  EXPECT_EQ(mismatch.e.reason, "N1 run has 3 samples, N2 run has 5 samples");
  EXPECT_FALSE(scalability(run(4, {1}), run(4, {1})).e.valid);  // N2 must exceed N1
  EXPECT_FALSE(scalability(run(0, {1}), run(4, {1})).phi.valid);
  const Scalability nan = scalability(run(2, {std::nan("")}), run(4, {1}));
  expectFinite(nan);
  EXPECT_EQ(nan.phi.reason, "P(N1) is not finite at T");
}

// Hand example: p(1) = [10, 10], n_ca(1) = [0.1, 0.2]; p(2) = [16, 18], n_ca(2) = [0.4, 0.6];
// p(4) = [30, 28], n_ca(4) = [1.6, 2.0].
const RunSeries kOne = run(1, {10, 20}, {10, 10}, {0.1, 0.2});
const RunSeries kTwo = run(2, {16, 34}, {16, 18}, {0.4, 0.6});
const RunSeries kFour = run(4, {30, 58}, {30, 28}, {1.6, 2.0});

TEST(SelfOrganization, TLostAndPLostByHand) {
  EXPECT_EQ(tLost(kTwo).value, V({0.2, 0.3}));  // 0.4/2, 0.6/2
  const MetricSeries one = pLost(kOne, kOne);
  EXPECT_EQ(one.value, V({10 * 0.1, 10 * 0.2}));  // P_lost(1) = p(1) t_lost^1 = [1, 2]
  const MetricSeries two = pLost(kOne, kTwo);     // 16*0.2 - 2*1 = 1.2; 18*0.3 - 2*2 = 1.4
  ASSERT_TRUE(two.valid);
  EXPECT_NEAR(two.value[0], 1.2, 1e-12);
  EXPECT_NEAR(two.value[1], 1.4, 1e-12);
  const MetricSeries four = pLost(kOne, kFour);  // 30*0.4 - 4*1 = 8; 28*0.5 - 4*2 = 6
  EXPECT_NEAR(four.value[0], 8.0, 1e-12);
  EXPECT_NEAR(four.value[1], 6.0, 1e-12);
}

TEST(SelfOrganization, ConstantConditionNonInteractingSwarmLosesNothing) {
  // Constant conditions: one robot delivers 4 per sample and avoids walls 0.25 of its ticks, so
  // P_lost(1) = 4 * 0.25 = 1 every sample. Four robots that never meet: p = 16, n_ca = 1.0, so
  // P_lost(4) = 16 * (1.0 / 4) - 4 * 1 = 0.
  const RunSeries one = run(1, {4, 8, 12}, {4, 4, 4}, {0.25, 0.25, 0.25});
  const RunSeries four = run(4, {16, 32, 48}, {16, 16, 16}, {1.0, 1.0, 1.0});
  EXPECT_EQ(pLost(one, one).value, V({1, 1, 1}));
  EXPECT_EQ(pLost(one, four).value, V({0, 0, 0}));
  // theta(4 vs 1) = 0 - 4 * 1 = -4 each sample: Z term 1 - 1/(1 + e^4) = 0.98201379.
  const SelfOrganization z = selfOrganization(one, one, four);
  EXPECT_EQ(z.theta.value, V({-4, -4, -4}));
  EXPECT_NEAR(z.z_mean.value, 0.9820137900, 1e-9);
  EXPECT_NEAR(z.z_sum.value, 3 * 0.9820137900, 1e-9);
}

TEST(SelfOrganization, ThetaAndZSumAndMean) {
  // m = 4 vs 2: theta = P_lost(4) - (4/2) P_lost(2) = [8 - 2.4, 6 - 2.8] = [5.6, 3.2].
  // Z terms: 1 - 1/(1 + e^-5.6) = 0.0036842399, 1 - 1/(1 + e^-3.2) = 0.0391657228.
  const SelfOrganization z = selfOrganization(kOne, kTwo, kFour);
  expectFinite(z);
  EXPECT_EQ(z.m_prev, 2u);
  EXPECT_EQ(z.m_cur, 4u);
  ASSERT_TRUE(z.z_sum.valid && z.z_mean.valid && z.theta.valid);
  EXPECT_NEAR(z.theta.value[0], 5.6, 1e-12);
  EXPECT_NEAR(z.theta.value[1], 3.2, 1e-12);
  EXPECT_NEAR(z.z_sum.value, 0.0036842399 + 0.0391657228, 1e-9);  // 0.0428499627
  EXPECT_NEAR(z.z_mean.value, 0.0428499627 / 2, 1e-9);
  // m = 2 vs 1: theta = P_lost(2) - 2 P_lost(1) = [1.2 - 2, 1.4 - 4] = [-0.8, -2.6]; terms
  // 1/(1 + e^-0.8) = 0.6899744811, 1/(1 + e^-2.6) = 0.9308615797; sum 1.6208360608, mean 0.8104180304.
  const SelfOrganization z2 = selfOrganization(kOne, kOne, kTwo);
  EXPECT_NEAR(z2.z_sum.value, 1.6208360608, 1e-9);
  EXPECT_NEAR(z2.z_mean.value, 0.8104180304, 1e-9);
  EXPECT_GT(z2.z_mean.value, 0.0);
  EXPECT_LT(z2.z_mean.value, 1.0);
}

TEST(SelfOrganization, AuthorsCodeUsesFinalFractionalLosses) {
  // Whole-run means: n_ca(1) = 0.15, n_ca(2) = 0.5, n_ca(4) = 1.8.
  // PL(2) = (0.5 - 2 * 0.15) / 2 = 0.1; PL(4) = (1.8 - 4 * 0.15) / 4 = 0.3; theta = 0.3 - 2 * 0.1 = 0.1;
  // Z = 1 - e^0.1 = -0.1051709181 (the paper's Z is 0.0428 here).
  const SelfOrganization a = selfOrganization(kOne, kTwo, kFour, kAuthors);
  expectFinite(a);
  ASSERT_EQ(a.theta.value.size(), 1u);
  EXPECT_NEAR(a.p_lost_prev.value[0], 0.1, 1e-12);
  EXPECT_NEAR(a.p_lost_cur.value[0], 0.3, 1e-12);
  EXPECT_NEAR(a.theta.value[0], 0.1, 1e-12);
  EXPECT_NEAR(a.z_sum.value, -0.1051709181, 1e-9);
  EXPECT_EQ(a.z_mean.value, a.z_sum.value);
  EXPECT_NE(a.z_sum.value, selfOrganization(kOne, kTwo, kFour).z_sum.value);
  // PL(1) = (n_ca(1) - n_ca(1)) / 1 = 0.
  EXPECT_EQ(selfOrganization(kOne, kOne, kTwo, kAuthors).p_lost_prev.value[0], 0.0);
}

TEST(SelfOrganization, ZeroPerformanceEmptyAndMismatchedRunsAreDefined) {
  // No deliveries: P_lost = 0 everywhere, theta = 0, each term 1 - 1/(1 + 1) = 0.5.
  const RunSeries one = run(1, {0, 0}, {0, 0}, {0.5, 0.5}), two = run(2, {0, 0}, {0, 0}, {1.5, 1});
  const SelfOrganization z = selfOrganization(one, one, two);
  expectFinite(z);
  EXPECT_DOUBLE_EQ(z.z_sum.value, 1.0);
  EXPECT_DOUBLE_EQ(z.z_mean.value, 0.5);
  for (Definitions d : {Definitions::kPaper, kAuthors}) {
    const SelfOrganization empty = selfOrganization(run(1, {}), run(1, {}), run(2, {}), d);
    expectFinite(empty);
    EXPECT_EQ(empty.z_mean.reason, "no samples");
    const SelfOrganization mismatch = selfOrganization(kOne, kTwo, run(4, {1}, {1}, {1}), d);
    expectFinite(mismatch);
    EXPECT_EQ(mismatch.z_sum.reason,
              "single-robot run has 2 samples, run of 2 has 2 samples, run of 4 has 1 sample");
    EXPECT_FALSE(selfOrganization(kOne, kFour, kTwo, d).z_sum.valid);  // m_i must exceed m_(i-1)
    EXPECT_FALSE(selfOrganization(kTwo, kTwo, kFour, d).z_sum.valid);  // not a single robot
  }
  const RunSeries short_p = run(2, {1, 2}, {1}, {0.1, 0.2});  // p has 1 sample, n_ca 2
  const SelfOrganization bad_p = selfOrganization(kOne, kOne, short_p);
  expectFinite(bad_p);
  EXPECT_EQ(bad_p.z_sum.reason, "run has 1 sample of p, 2 of n_ca");
  EXPECT_FALSE(tLost(run(0, {1}, {1}, {1})).valid);
}

TEST(Flexibility, MinMaxMapping) {
  EXPECT_EQ(minMaxMap({0.5, 1.0, 0.75}, 2, 6), V({2, 6, 4}));  // (6-2)(x - 0.5)/0.5 + 2
  EXPECT_EQ(minMaxMap({0.8, 0.8, 0.8}, 2, 6), V({4, 4, 4}));   // constant -> middle (2 + 6) / 2
  EXPECT_TRUE(minMaxMap({}, 2, 6).empty());
  // Constant s in P_R*: min P_ideal = 2, max = 6 -> 4 everywhere.
  EXPECT_EQ(reactivityIdeal({0.8, 0.8, 0.8}, {2, 6, 4}), V({4, 4, 4}));
}

TEST(Flexibility, IdealCurvesUnderThrottleAndBoost) {
  // Throttle (s < 1): P_R* maps s in [0.5, 1] onto [min, max] of P_ideal = [4, 8].
  EXPECT_EQ(reactivityIdeal({1, 1, 0.5, 0.5}, {4, 8, 6, 6}), V({8, 8, 4, 4}));
  // Boost (s > 1): s in [1, 1.5] onto P_ideal's [3, 5].
  EXPECT_EQ(reactivityIdeal({1, 1.5, 1.5}, {3, 5, 4}), V({3, 5, 5}));
  // P_A*: an adverse deviation is resisted fully (P_ideal), a beneficial one exploited (P_ideal s).
  EXPECT_EQ(adaptabilityIdeal({1, 0.5}, {4, 6}), V({4, 6}));    // s <= 1: P_ideal
  EXPECT_EQ(adaptabilityIdeal({1.25, 2}, {4, 6}), V({5, 12}));  // 4 * 1.25, 6 * 2
  EXPECT_EQ(adaptabilityIdeal({1.0, 1.5, 0.5}, {4, 8, 6}), V({4, 12, 6}));
}

TEST(Flexibility, ReactivityAndAdaptabilityOnTinySeries) {
  // R: P_R* = [8, 8, 4, 4] vs p = [8, 6, 4, 4]; p's 6 must meet an 8 or a 4 -> DTW = 2.
  const RunSeries ideal = run(4, {}, {4, 8, 6, 6}), thr = run(4, {}, {8, 6, 4, 4}, {}, {1, 1, 0.5, 0.5});
  const Flexibility r = reactivity(ideal, thr);
  expectFinite(r);
  EXPECT_EQ(r.ideal, V({8, 8, 4, 4}));
  EXPECT_EQ(r.distance.value, 2.0);
  // A: ideal p = [4, 4, 4, 4], boost s = [1, 2, 2, 2] -> P_A* = [4, 8, 8, 8]; the swarm follows one
  // sample late, p = [4, 4, 8, 8]: 1-D DTW warps it to 0 (paper) and the band 0 forbids that:
  // diagonal |8 - 4| = 4.
  const RunSeries flat = run(4, {}, {4, 4, 4, 4}), lag = run(4, {}, {4, 4, 8, 8}, {}, {1, 2, 2, 2});
  const Flexibility a = adaptability(flat, lag);
  expectFinite(a);
  EXPECT_EQ(a.ideal, V({4, 8, 8, 8}));
  EXPECT_EQ(a.distance.value, 0.0);
  EXPECT_EQ(adaptability(flat, lag, Definitions::kPaper, 0).distance.value, 4.0);
  // authors_code_2019: points (tick, value) with ticks 1000, 2000, ...; a warp step costs >= 1000 in
  // time, so the diagonal (time cost 0, value cost 4) is optimal: A = 4 instead of 0.
  EXPECT_EQ(adaptability(flat, lag, kAuthors).distance.value, 4.0);
  // With a 1-tick interval the warp is cheap: (0,0) 0, (0,1) |1-2| = 1, (1,2) |2-3| = 1, (2,2) 0,
  // (3,3) 0 -> 2 (any path visits a cell with x1 and one with y1, each costing >= 1, or (1,1) = 4).
  RunSeries flat1 = flat, lag1 = lag;
  flat1.interval = lag1.interval = 1;
  EXPECT_EQ(adaptability(flat1, lag1, kAuthors).distance.value, 2.0);
  EXPECT_EQ(reactivity(ideal, thr, kAuthors).distance.value, 2.0);  // diagonal 0 + 2 + 0 + 0
}

TEST(Flexibility, ZeroPerformanceEmptyAndMismatchedRunsAreDefined) {
  // Nothing delivered: P_R* maps onto [0, 0] (constant -> 0), P_A* = 0 * s = 0; both distances 0.
  const RunSeries idle = run(8, {}, {0, 0}), idle_run = run(8, {}, {0, 0}, {}, {1, 0.5});
  for (const Flexibility& f : {reactivity(idle, idle_run), adaptability(idle, idle_run)}) {
    expectFinite(f);
    EXPECT_TRUE(f.distance.valid);
    EXPECT_EQ(f.distance.value, 0.0);
    EXPECT_EQ(f.ideal, V({0, 0}));
  }
  const RunSeries three = run(8, {}, {1, 2, 3}), five = run(8, {}, {1, 2, 3, 4, 5}, {}, {1, 1, 1, 1, 1});
  for (Definitions d : {Definitions::kPaper, kAuthors}) {
    const Flexibility m = reactivity(three, five, d);
    expectFinite(m);
    EXPECT_EQ(m.distance.reason, "reference run has 3 samples, run has 5");
    EXPECT_TRUE(m.ideal.empty());
    EXPECT_EQ(adaptability(run(8, {}), five, d).distance.reason, "reference run has no samples");
    EXPECT_EQ(adaptability(three, run(8, {}), d).distance.reason, "run has no samples");
    EXPECT_EQ(reactivity(three, run(8, {}, {1, 2, 3}), d).distance.reason, "run has 3 samples of p, 0 of s");
    EXPECT_EQ(reactivity(run(4, {}, {1}), run(8, {}, {1}, {}, {1}), d).distance.reason,
              "reference run has 4 robots, run has 8");
    const Flexibility nan = adaptability(three, run(8, {}, {1, 2, 3}, {}, {1, std::nan(""), 1}), d);
    expectFinite(nan);
    EXPECT_EQ(nan.distance.reason, "s is not finite at sample 1");
  }
}

TEST(Aggregation, MeanAndConfidenceIntervalByHand) {
  // t(0.975, 1) = tan(0.475 pi) = 12.7062047364; t(0.975, 2) = 0.95 / sqrt(2 * 0.975 * 0.025) = 4.3026527299.
  EXPECT_NEAR(studentT95(1), 12.7062047364, 1e-9);
  EXPECT_NEAR(studentT95(2), 4.3026527299, 1e-9);
  EXPECT_NEAR(studentT95(30), 2.0422724563, 1e-9);
  EXPECT_EQ(studentT95(0), 0.0);
  // Three runs, P at sample 0 = 1, 2, 3: mean 2, sd = sqrt((1 + 0 + 1) / 2) = 1,
  // half-width = 4.3026527299 * 1 / sqrt(3) = 2.4841377118. Sample 1: 2, 2, 2 -> mean 2, half-width 0.
  std::vector<RunSeries> runs = {run(4, {1, 2}, {1, 1}, {0.5, 1}, {1, 1}),
                                 run(4, {2, 2}, {2, 0}, {1, 1}, {1, 1}),
                                 run(4, {3, 2}, {3, 2}, {1.5, 1}, {1, 1})};
  const AggregatedRuns agg = aggregateRuns(runs);
  ASSERT_TRUE(agg.valid) << agg.reason;
  EXPECT_EQ(agg.runs, 3u);
  EXPECT_FALSE(agg.truncated);
  EXPECT_EQ(agg.mean.swarm_size, 4u);
  EXPECT_EQ(agg.mean.P, V({2, 2}));
  EXPECT_NEAR(agg.ci95.P[0], 2.4841377118, 1e-9);
  EXPECT_EQ(agg.ci95.P[1], 0.0);
  EXPECT_EQ(agg.mean.p, V({2, 1}));                // (1 + 2 + 3) / 3, (1 + 0 + 2) / 3
  EXPECT_NEAR(agg.ci95.p[1], 2.4841377118, 1e-9);  // 1, 0, 2: sd 1 as well
  EXPECT_EQ(agg.mean.n_ca, V({1, 1}));
  EXPECT_NEAR(agg.ci95.n_ca[0], 1.2420688559, 1e-9);  // 0.5, 1, 1.5: sd 0.5 -> half of 2.4841377118
  EXPECT_EQ(agg.mean.s, V({1, 1}));
  // One run: half-width 0.
  const AggregatedRuns single = aggregateRuns({runs[0]});
  EXPECT_EQ(single.mean.P, V({1, 2}));
  EXPECT_EQ(single.ci95.P, V({0, 0}));
  // Unequal lengths: the common prefix, and the note says so.
  runs[1].P.push_back(7);
  const AggregatedRuns cut = aggregateRuns(runs);
  EXPECT_TRUE(cut.valid && cut.truncated);
  EXPECT_EQ(cut.mean.P.size(), 2u);
  EXPECT_EQ(cut.note, "P: runs have 2 to 3 samples, using the common 2");
  // Runs that cannot be pooled.
  EXPECT_EQ(aggregateRuns({}).reason, "no runs");
  runs[2].swarm_size = 8;
  EXPECT_EQ(aggregateRuns(runs).reason, "run 2 has 8 robots, run 0 has 4");
  EXPECT_TRUE(aggregateSeries({}).mean.empty());
}

}  // namespace
}  // namespace swarm_forage
