// The robustness measures (docs/robustness-measures.md) against hand-computed cases, every definition; the
// arithmetic is beside each number. Also the robots out of the swarm, counted from population records,
// against the queue the PD measure assumes.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/robustness.hpp"
#include "swarm_forage/core/metrics/robustness_evaluation.hpp"
#include "swarm_forage/core/metrics/run_library.hpp"
#include "swarm_forage/core/run/run_records.hpp"
#include "swarm_forage/core/world/population.hpp"

namespace swarm_forage {
namespace {

using V = std::vector<double>;
constexpr auto kPaper = Definitions::kPaper;
constexpr auto kAuthors = Definitions::kAuthorsCode;
constexpr auto k2019 = Definitions::kAuthorsCode2019;
constexpr auto k2020 = Definitions::kAuthorsCode2020;

double sigma(double x) { return 1.0 / (1.0 + std::exp(-x)); }
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

RunSeries curve(V P, uint32_t n = 4, uint32_t interval = 1000) {
  RunSeries r;
  r.swarm_size = n;
  r.interval = interval;
  r.P = P;
  r.p = V(P.size(), 0.0);
  r.n_ca = V(P.size(), 0.0);
  r.s = V(P.size(), 1.0);
  return r;
}

PopulationRates rates(double death, double birth, double malfunction, double repair, uint32_t max_size = 4) {
  PopulationRates r;
  r.death = death;
  r.birth = birth;
  r.malfunction = malfunction;
  r.repair = repair;
  r.max_size = max_size;
  return r;
}

TEST(RobustnessWords, SplitsNoiseAndPopulationWordsFromTheRest) {
  const RobustnessWords w = robustnessWords(
      "robot/radius=0.085 noise/proximity=gaussian:0.01 noise/ground=0.05 population/death=0.0001 "
      "population/birth=0 population/malfunction=0.001 population/repair=0.002 population/max_size=64 "
      "start_margin=1");
  EXPECT_EQ(w.problem, "");
  EXPECT_EQ(w.noise, "noise/proximity=gaussian:0.01 noise/ground=0.05");
  EXPECT_EQ(w.noise_level, 0.05);  // the largest of 0.01 and 0.05
  EXPECT_EQ(w.population, rates(1e-4, 0, 1e-3, 2e-3, 64));
  EXPECT_EQ(w.without_noise,
            "robot/radius=0.085 population/death=0.0001 population/birth=0 population/malfunction=0.001 "
            "population/repair=0.002 population/max_size=64 start_margin=1");
  EXPECT_EQ(w.without_population,
            "robot/radius=0.085 noise/proximity=gaussian:0.01 noise/ground=0.05 start_margin=1");

  const RobustnessWords plain = robustnessWords("robot/radius=0.085 start_margin=1");
  EXPECT_EQ(plain.noise, "");
  EXPECT_FALSE(plain.population.enabled());
  EXPECT_EQ(plain.without_noise, "robot/radius=0.085 start_margin=1");
  EXPECT_EQ(plain.without_population, plain.without_noise);

  EXPECT_EQ(robustnessWords("noise/light=gaussian:x").problem,
            "cannot read the noise level of 'noise/light=gaussian:x'");
  EXPECT_EQ(robustnessWords("population/death=-1").problem,
            "cannot read the population word 'population/death=-1'");
  EXPECT_EQ(robustnessWords("population/age=1").problem,
            "cannot read the population word 'population/age=1'");
}

TEST(Robustness, LogisticSpreadIsSigmaMinusSigmaOfMinusX) {
  EXPECT_NEAR(logisticSpread(2.0), sigma(2.0) - sigma(-2.0), 1e-15);  // 0.76159415595576...
  EXPECT_NEAR(logisticSpread(2.0), 0.7615941559557649, 1e-15);
  EXPECT_EQ(logisticSpread(0.0), 0.0);
  EXPECT_EQ(logisticSpread(1e6), 1.0);  // no overflow
  EXPECT_EQ(logisticSpread(-1e6), -1.0);
}

TEST(SaaRobustness, PaperIsDtwOnCountsAuthorsCodeOnTheirCurve) {
  // run P = {10, 10, 30}, noise-free P = {10, 30, 30}.
  // Values only: the path (0,0) (1,0) (2,1) (2,2) costs |10-10| + |10-10| + |30-30| + |30-30| = 0.
  const SaaRobustness paper = saaRobustness(curve({10, 30, 30}), curve({10, 10, 30}), kPaper);
  ASSERT_TRUE(paper.distance.valid) << paper.distance.reason;
  EXPECT_EQ(paper.distance.value, 0.0);
  EXPECT_EQ(paper.normalized.value, 0.0);  // sigma(0) - sigma(0): the best value
  // authors_code: the blocks per tick so far, {10/1000, 10/2000, 30/3000} = {0.01, 0.005, 0.01} against
  // {0.01, 0.015, 0.01}, at rows 0, 1, 2 with L1 cost: a warp step adds >= 1, so the diagonal is optimal:
  // 0 + 0.01 + 0 = 0.01.
  const SaaRobustness authors = saaRobustness(curve({10, 30, 30}), curve({10, 10, 30}), kAuthors);
  ASSERT_TRUE(authors.distance.valid) << authors.distance.reason;
  EXPECT_NEAR(authors.distance.value, 0.01, 1e-15);
  EXPECT_NEAR(authors.normalized.value, sigma(-0.01) - sigma(0.01), 1e-15);

  // run {10, 20, 30} against {10, 25, 40}: costs |x - y| row by row {0 15 30; 10 5 20; 20 5 10};
  // cumulative D: {0 15 45; 10 5 25; 30 10 15}: d = 15 (the diagonal 0 + 5 + 10).
  const SaaRobustness d15 = saaRobustness(curve({10, 25, 40}), curve({10, 20, 30}), kPaper);
  EXPECT_EQ(d15.distance.value, 15.0);
  EXPECT_NEAR(d15.normalized.value, 1.0 / (1.0 + std::exp(15.0)) - 1.0 / (1.0 + std::exp(-15.0)), 1e-15);
  EXPECT_LT(d15.normalized.value, 0.0);
  EXPECT_GT(d15.normalized.value, -1.0);
}

TEST(SaaRobustness, AuthorsCodeWarpsTheirCurveBySampleRow) {
  // Sampled every 2 ticks: run P = {8, 16, 48}, noise-free P = {8, 32, 48}.
  const RunSeries run = curve({8, 16, 48}, 4, 2), reference = curve({8, 32, 48}, 4, 2);
  // The authors' curve, blocks per tick so far: {8/2, 16/4, 48/6} = {4, 4, 8} and {8/2, 32/4, 48/6} = {4, 8,
  // 8}.
  EXPECT_EQ(cumulativeAverage(run), (V{4, 4, 8}));
  EXPECT_EQ(cumulativeAverage(reference), (V{4, 8, 8}));

  // authors_code: points (row, value), rows 0, 1, 2, cost |i - j| + |a_i - b_j|:
  //   c = {0 5 6; 1 4 5; 6 1 0}; D = {0 5 11; 1 4 9; 7 2 2}: d = 2 along (0,0) (1,0) (2,1) (2,2), 0 + 1 + 1 +
  //   0 (the diagonal costs 0 + 4 + 0).
  const SaaRobustness authors = saaRobustness(reference, run, kAuthors);
  ASSERT_TRUE(authors.distance.valid) << authors.distance.reason;
  EXPECT_EQ(authors.distance.value, 2.0);
  EXPECT_NEAR(authors.normalized.value, sigma(-2.0) - sigma(2.0), 1e-15);

  // authors_code_2020: points (tick, value), ticks 2, 4, 6: a warp step costs 2 more, so the warped path
  // 0 + 2 + 2 + 0 ties the diagonal 0 + 4 + 0: d = 4.
  const SaaRobustness sierra = saaRobustness(reference, run, k2020);
  ASSERT_TRUE(sierra.distance.valid) << sierra.distance.reason;
  EXPECT_EQ(sierra.distance.value, 4.0);

  // paper: 1-D on the counts, c = {0 24 40; 8 16 32; 40 16 0}: the diagonal 0 + 16 + 0 = 16 is optimal.
  EXPECT_EQ(saaRobustness(reference, run, kPaper).distance.value, 16.0);
}

TEST(SaaRobustness, RefusesWhatCannotBeCompared) {
  const SaaRobustness shorter = saaRobustness(curve({10, 20}), curve({10, 20, 30}), kPaper);
  EXPECT_FALSE(shorter.distance.valid);
  EXPECT_EQ(shorter.distance.reason, "reference run has 2 samples, run has 3");
  EXPECT_EQ(saaRobustness(curve({1}, 4, 500), curve({1}), kPaper).distance.reason,
            "reference run is sampled every 500 ticks, run every 1000");
  EXPECT_EQ(saaRobustness(curve({}), curve({}), kPaper).distance.reason, "run has no samples");
  EXPECT_EQ(saaRobustness(curve({1, NAN}), curve({1, 2}), kPaper).distance.reason,
            "P is not finite at sample 1");
  const SaaRobustness old = saaRobustness(curve({1}), curve({1}), k2019);
  EXPECT_FALSE(old.distance.valid);
  EXPECT_TRUE(contains(old.distance.reason, "2019 code has no robustness measure")) << old.distance.reason;
}

TEST(PdRobustness, ExpectedTimeOutOfTheSwarm) {
  // lambda = 1e-4 + 1e-3 = 1.1e-3, mu = 5e-4 + 2e-3 = 2.5e-3, mu - lambda = 1.4e-3.
  const PopulationRates r = rates(1e-4, 5e-4, 1e-3, 2e-3);
  // paper: 1/1.4e-3 - 1/2.5e-3 = 714.2857... - 400 = 314.2857...
  const MetricValue paper = expectedTimeOut(r, 20000, kPaper);
  ASSERT_TRUE(paper.valid) << paper.reason;
  EXPECT_NEAR(paper.value, 1.0 / 1.4e-3 - 400.0, 1e-9);
  EXPECT_NEAR(paper.value, 314.2857142857143, 1e-9);
  // authors_code: titerra's rho = 0.44, L = rho^2/(1 - rho) = 0.345714..., W = L/lambda + 1/mu
  //   = 314.2857... + 400 = 714.2857... = 1/(mu - lambda).
  const MetricValue authors = expectedTimeOut(r, 20000, kAuthors);
  ASSERT_TRUE(authors.valid) << authors.reason;
  const double rho = 1.1e-3 / 2.5e-3;
  EXPECT_NEAR(authors.value, rho * rho / (1 - rho) / 1.1e-3 + 1 / 2.5e-3, 1e-9);
  EXPECT_NEAR(authors.value, 714.2857142857143, 1e-9);

  // No arrivals (birth only): paper 1/mu - 1/mu = 0; authors_code the limit 1/mu = 1000.
  EXPECT_EQ(expectedTimeOut(rates(0, 1e-3, 0, 0), 20000, kPaper).value, 0.0);
  EXPECT_NEAR(expectedTimeOut(rates(0, 1e-3, 0, 0), 20000, kAuthors).value, 1000.0, 1e-9);

  // Pure death: no steady state in the paper's formula; T in the authors' code.
  const MetricValue death = expectedTimeOut(rates(1e-4, 0, 0, 0), 20000, kPaper);
  EXPECT_FALSE(death.valid);
  EXPECT_TRUE(contains(death.reason,
                       "no steady state: lambda = death + malfunction = 0.0001 >= mu = birth + "
                       "repair = 0 per tick"))
      << death.reason;
  EXPECT_TRUE(contains(death.reason, "authors_code_2020 and authors_code take T_bar = T under pure death"))
      << death.reason;
  EXPECT_EQ(expectedTimeOut(rates(1e-4, 0, 0, 0), 20000, kAuthors).value, 20000.0);
  EXPECT_EQ(expectedTimeOut(rates(1e-4, 0, 1e-3, 2e-3), 20000, kAuthors).value, 20000.0);  // as titerra

  // Unstable (lambda 3e-3 >= mu 2e-3) in both; lambda = mu too.
  for (Definitions d : {kPaper, kAuthors}) {
    EXPECT_FALSE(expectedTimeOut(rates(0, 0, 3e-3, 2e-3), 20000, d).valid);
    EXPECT_TRUE(contains(expectedTimeOut(rates(0, 0, 2e-3, 2e-3), 20000, d).reason, "no steady state"));
  }
  EXPECT_EQ(expectedTimeOut(rates(0, 0, 0, 0), 20000, kPaper).reason,
            "no population dynamics (every rate is 0)");
  EXPECT_FALSE(expectedTimeOut(r, 20000, k2019).valid);
  EXPECT_FALSE(expectedTimeOut(r, 0, kPaper).valid);
}

TEST(PdRobustness, ThetaAgainstTheReference) {
  const PopulationRates r = rates(1e-4, 5e-4, 1e-3, 2e-3);
  // paper: weight (T - T_bar)/T = (20000 - 314.2857...)/20000 = 0.98428571...;
  // theta = 80 - 0.98428571... * 100 = -18.428571...
  const PdRobustness paper = pdRobustness(80, 100, 20000, r, PopulationRates{}, kPaper);
  ASSERT_TRUE(paper.theta.valid) << paper.theta.reason;
  EXPECT_NEAR(paper.weight, (20000 - 314.2857142857143) / 20000, 1e-12);
  EXPECT_NEAR(paper.theta.value, -18.428571428571428, 1e-9);
  EXPECT_NEAR(paper.normalized.value, sigma(paper.theta.value) - sigma(-paper.theta.value), 1e-15);

  // authors_code, reference = half the rates: lambda 5.5e-4, mu 1.25e-3, W0 = 1/7e-4 = 1428.57...;
  // W = 714.28...; weight W0/W = 2; theta = 80 - 2 * 100 = -120.
  // On the last row of their curve, blocks per tick: theta = 80/20000 - 2 * 100/20000 = -0.006.
  const PdRobustness authors = pdRobustness(80, 100, 20000, r, rates(5e-5, 2.5e-4, 5e-4, 1e-3), kAuthors);
  ASSERT_TRUE(authors.theta.valid) << authors.theta.reason;
  EXPECT_NEAR(authors.weight, 2.0, 1e-12);
  EXPECT_NEAR(authors.theta.value, -0.006, 1e-15);
  EXPECT_NEAR(authors.normalized.value, sigma(-0.006) - sigma(0.006), 1e-15);
  // Pure death in the authors' code: W0 = W = T, theta = (80 - 100)/20000.
  EXPECT_NEAR(pdRobustness(80, 100, 20000, rates(2e-4, 0, 0, 0), rates(1e-4, 0, 0, 0), kAuthors).theta.value,
              -0.001, 1e-15);
  // An unstable queue has no number, in either definition.
  const PdRobustness unstable = pdRobustness(80, 100, 20000, rates(0, 0, 3e-3, 2e-3), r, kPaper);
  EXPECT_FALSE(unstable.theta.valid);
  EXPECT_EQ(unstable.theta.value, 0.0);
  EXPECT_TRUE(contains(unstable.theta.reason, "no steady state")) << unstable.theta.reason;
  EXPECT_FALSE(pdRobustness(80, 100, 20000, r, rates(0, 0, 3e-3, 2e-3), kAuthors).theta.valid);
}

TEST(PdRobustness, Sierra2020EdgeCasesAsCalcTaskedSwarmTime) {
  // authors_code_2020: theta = P - (T_S / T) P_ideal with T_S = T - T_bar from sierra's
  // calc_tasked_swarm_time; P = 80, P_ideal = 100, T = 20000.
  const auto theta = [](const PopulationRates& r) { return pdRobustness(80, 100, 20000, r, {}, k2020); };

  // Pure death (death > 0, birth = 0, whatever malfunction and repair): T_S = 0, theta = P(N) = 80.
  for (const PopulationRates& r : {rates(1e-4, 0, 0, 0), rates(1e-4, 0, 1e-3, 2e-3)}) {
    const PdRobustness death = theta(r);
    ASSERT_TRUE(death.theta.valid) << death.theta.reason;
    EXPECT_EQ(death.time_out.value, 20000.0);
    EXPECT_EQ(death.weight, 0.0);
    EXPECT_EQ(death.theta.value, 80.0);
    EXPECT_EQ(death.normalized.value, logisticSpread(80.0));
  }
  // mu = lambda (1e-3 + 1e-3 against 1e-3 + 1e-3): 1/(mu - lambda) divides by zero, T_S = T: theta = 80 -
  // 100. mu = 0 without pure death (malfunction only): 1/mu divides by zero, the same.
  for (const PopulationRates& r :
       {rates(1e-3, 1e-3, 1e-3, 1e-3), rates(0, 0, 2e-3, 2e-3), rates(0, 0, 1e-3, 0)}) {
    const PdRobustness equal = theta(r);
    ASSERT_TRUE(equal.theta.valid) << equal.theta.reason;
    EXPECT_EQ(equal.time_out.value, 0.0);
    EXPECT_EQ(equal.weight, 1.0);
    EXPECT_EQ(equal.theta.value, -20.0);
  }
  // lambda > mu (3e-3 > 2e-3): T_bar = 1/(-1e-3) - 1/2e-3 = -1000 - 500 = -1500, T_S = 21500,
  // weight 1.075: theta = 80 - 107.5 = -27.5 (no "no steady state": their code gives a number).
  const PdRobustness unstable = theta(rates(0, 0, 3e-3, 2e-3));
  ASSERT_TRUE(unstable.theta.valid) << unstable.theta.reason;
  EXPECT_NEAR(unstable.time_out.value, -1500.0, 1e-9);
  EXPECT_NEAR(unstable.weight, 1.075, 1e-12);
  EXPECT_NEAR(unstable.theta.value, -27.5, 1e-9);
  // A stable queue: the paper's T_bar and theta (ThetaAgainstTheReference): -18.428571...
  const PdRobustness stable = theta(rates(1e-4, 5e-4, 1e-3, 2e-3));
  EXPECT_NEAR(stable.time_out.value, 314.2857142857143, 1e-9);
  EXPECT_NEAR(stable.theta.value, -18.428571428571428, 1e-9);
  // Nothing to compute without rates or ticks, as the other definitions.
  EXPECT_FALSE(theta(rates(0, 0, 0, 0)).theta.valid);
  EXPECT_FALSE(pdRobustness(80, 100, 0, rates(1e-4, 0, 0, 0), {}, k2020).theta.valid);
}

// ---- The queue, measured --------------------------------------------------------------------------

PopulationRecord tick(uint64_t t, uint32_t active, std::vector<uint32_t> deaths = {},
                      std::vector<uint32_t> births = {}, std::vector<uint32_t> malfunctions = {},
                      std::vector<uint32_t> repairs = {}) {
  PopulationRecord p;
  p.tick = t;
  p.active = active;
  p.max_size = 4;
  p.deaths = deaths;
  p.births = births;
  p.malfunctions = malfunctions;
  p.repairs = repairs;
  return p;
}

TEST(OutOfSwarm, OutagesAndRobotsOutFromPopulationRecords) {
  OutOfSwarmCounter c;
  c.add(tick(0, 3, {2}));               // robot 2 dies: 1 out
  c.add(tick(1, 2, {}, {}, {0}));       // robot 0 awaits repair: 2 out
  c.add(tick(2, 2));                    // 2 out
  c.add(tick(3, 4, {}, {2}, {}, {0}));  // 2 born again after 3 ticks, 0 repaired after 2: 0 out
  c.add(tick(4, 4, {1}, {1}));          // robot 1 dies and is born again in the same tick: out 0 ticks
  c.add(tick(5, 3, {}, {}, {3}));       // robot 3 awaits repair at the end: 1 out, still going
  EXPECT_FALSE(c.totals(7));            // not the whole run
  const auto t = c.totals(6);
  ASSERT_TRUE(t);
  EXPECT_EQ(t->ticks, 6u);
  EXPECT_EQ(t->robot_ticks, 6.0);  // 1 + 2 + 2 + 0 + 0 + 1
  EXPECT_EQ(t->returns, 3u);
  EXPECT_EQ(t->return_ticks, 5.0);  // 3 + 2 + 0
  EXPECT_EQ(t->open, 1u);
  EXPECT_EQ(t->meanOut(), 1.0);
  EXPECT_NEAR(*t->meanTimeOut(), 5.0 / 3.0, 1e-15);

  // A robot that dies while awaiting repair is out from its malfunction until its id is born again.
  OutOfSwarmCounter d;
  d.add(tick(0, 3, {}, {}, {1}));
  d.add(tick(1, 3, {1}));
  d.add(tick(2, 4, {}, {1}));
  EXPECT_EQ(d.totals(3)->return_ticks, 2.0);
  EXPECT_EQ(d.totals(3)->returns, 1u);
  // A tick missing (or a run followed from a later tick): no totals.
  OutOfSwarmCounter gap;
  gap.add(tick(0, 4));
  gap.add(tick(2, 4));
  EXPECT_FALSE(gap.totals(2));
  EXPECT_FALSE(gap.totals(3));
  OutOfSwarmCounter late;
  late.add(tick(1, 4));
  EXPECT_FALSE(late.totals(1));
  // Death only: nobody comes back, so there is no mean time out; the robots out are measured.
  OutOfSwarmCounter death;
  death.add(tick(0, 3, {0}));
  death.add(tick(1, 3));
  EXPECT_FALSE(death.totals(2)->meanTimeOut());
  EXPECT_EQ(death.totals(2)->meanOut(), 1.0);
}

TEST(OutOfSwarm, QueueCheckFlagsAMeasuredValueMoreThanTwentyPercentOff) {
  // death 0.01, birth 0.02: lambda 0.01, mu 0.02: W = 1/0.01 = 100 ticks, L = 0.01/0.01 = 1 robot.
  const PopulationRates r = rates(0.01, 0.02, 0, 0);
  const QueueCheck none = queueCheck(r, std::nullopt);
  EXPECT_NEAR(*none.time_out_queue, 100.0, 1e-12);
  EXPECT_NEAR(*none.out_queue, 1.0, 1e-12);
  EXPECT_FALSE(none.time_out_measured || none.out_measured || none.differs);
  // Measured 91 ticks (9 % off) and 0.43 robots (57 % off): flagged.
  OutOfSwarm m;
  m.ticks = 1000;
  m.robot_ticks = 430;
  m.returns = 10;
  m.return_ticks = 910;
  const QueueCheck off = queueCheck(r, m);
  EXPECT_NEAR(*off.time_out_measured, 91.0, 1e-12);
  EXPECT_NEAR(*off.out_measured, 0.43, 1e-12);
  EXPECT_EQ(off.outages, 10u);
  EXPECT_EQ(off.differs, std::optional<bool>(true));
  // 0.81 robots (19 % off) and 91 ticks: within 20 % both.
  m.robot_ticks = 810;
  EXPECT_EQ(queueCheck(r, m).differs, std::optional<bool>(false));
  // 121 ticks (21 % off): flagged on the time alone.
  m.return_ticks = 1210;
  EXPECT_EQ(queueCheck(r, m).differs, std::optional<bool>(true));
  // No outage ended: the robots out alone are compared.
  m.returns = 0;
  m.return_ticks = 0;
  const QueueCheck count_only = queueCheck(r, m);
  EXPECT_FALSE(count_only.time_out_measured);
  EXPECT_EQ(count_only.differs, std::optional<bool>(false));
  // No steady state (death only): no prediction, nothing to flag.
  const QueueCheck unstable = queueCheck(rates(0.01, 0, 0, 0), m);
  EXPECT_FALSE(unstable.time_out_queue || unstable.out_queue || unstable.differs);
  EXPECT_NEAR(*unstable.out_measured, 0.81, 1e-12);
}

/// The processes alone, as the world runs them (every spot free), counted: totals over `seeds` runs.
OutOfSwarm simulated(const PopulationConfig& c, uint32_t n, uint64_t ticks, uint32_t seeds) {
  OutOfSwarm all;
  for (uint32_t seed = 1; seed <= seeds; ++seed) {
    PopulationDynamics pd;
    pd.reset(c, seed, n);
    OutOfSwarmCounter counter;
    for (uint64_t t = 0; t < ticks; ++t) {
      const PopulationEvents& e = pd.update(t, [](uint32_t, bool) { return true; });
      PopulationRecord p;
      p.tick = t;
      p.active = e.active;
      p.max_size = n;
      p.deaths = e.deaths;
      p.births = e.births;
      p.malfunctions = e.malfunctions;
      p.repairs = e.repairs;
      counter.add(p);
    }
    all.add(*counter.totals(ticks));
  }
  return all;
}

TEST(OutOfSwarm, TheRepairQueueIsTheQueueBirthAsCosmDoesItIsNot) {
  // Malfunction 0.01, repair 0.02 per tick: a FIFO queue served at Poisson times, the M/M/1 the measure
  // assumes: W = 100, L = 1 (a little under: the discrete processes run slightly faster than their rates).
  PopulationConfig repair;
  repair.malfunction = 0.01;
  repair.repair = 0.02;
  const OutOfSwarm q = simulated(repair, 16, 100000, 4);
  EXPECT_GT(q.returns, 3000u);  // about 4 x 1000 outages
  EXPECT_NEAR(*q.meanTimeOut(), 100.0, 20.0);
  EXPECT_NEAR(*q.meanOut(), 1.0, 0.2);
  EXPECT_EQ(queueCheck(rates(0, 0, 0.01, 0.02), q).differs, std::optional<bool>(false));
  // Every tick out belongs to an outage: those that ended and those still going at each run's end.
  EXPECT_GE(q.robot_ticks, q.return_ticks);

  // Death 0.01, birth 0.02: a birth due while the swarm is full stays due, so a death is often refilled at
  // once. Far fewer robots are out than the queue's L = 1, and the check says so.
  PopulationConfig death;
  death.death = 0.01;
  death.birth = 0.02;
  const OutOfSwarm b = simulated(death, 16, 100000, 4);
  EXPECT_LT(*b.meanOut(), 0.7);
  EXPECT_EQ(queueCheck(rates(0.01, 0.02, 0, 0), b).differs, std::optional<bool>(true));
}

// ---- Against a library ----------------------------------------------------------------------------

const std::string kBase = "robot/radius=0.085";
const std::string kNoise = kBase + " noise/proximity=gaussian:0.02";
std::string pd(const std::string& rates) { return kBase + " " + rates; }
const std::string kPd1 =
    pd("population/death=0.0001 population/birth=0.0005 population/malfunction=0.001 population/repair=0.002 "
       "population/max_size=4");
const std::string kPd2 =
    pd("population/death=0.0002 population/birth=0.001 population/malfunction=0.002 population/repair=0.004 "
       "population/max_size=4");
const std::string kDeath =
    pd("population/death=0.0001 population/birth=0 population/malfunction=0 population/repair=0 "
       "population/max_size=4");

RunKey key(const std::string& world) {
  RunKey k{"crw", "32x16", 4, Condition{}, {}};
  k.setup.ticks = 3000;
  k.setup.interval = 1000;
  k.setup.world_constants = world;
  return k;
}
RunRecord record(const std::string& world, uint32_t seed, V P) {
  return RunRecord{key(world), seed, "test", curve(P)};
}

/// `pd1_seed1`, `pd1_seed2`: what the kPd1 runs' population records show (none by default).
RunLibrary library(std::optional<OutOfSwarm> pd1_seed1 = std::nullopt,
                   std::optional<OutOfSwarm> pd1_seed2 = std::nullopt) {
  RunLibrary lib;
  lib.add(record(kBase, 1, {10, 30, 50}));
  lib.add(record(kBase, 2, {10, 20, 30}));  // mean {10, 25, 40}
  lib.add(record(kNoise, 1, {10, 20, 30}));
  lib.add(record(kNoise, 2, {10, 20, 30}));
  lib.add(record(kNoise, 3, {10, 20, 30}));  // seed 3 has no noise-free partner
  RunRecord pd1 = record(kPd1, 1, {10, 20, 40});
  pd1.out_of_swarm = pd1_seed1;
  lib.add(pd1);
  pd1 = record(kPd1, 2, {10, 20, 20});  // mean {10, 20, 30}
  pd1.out_of_swarm = pd1_seed2;
  lib.add(pd1);
  lib.add(record(kPd2, 1, {10, 20, 24}));
  lib.add(record(kPd2, 2, {10, 20, 36}));  // mean {10, 20, 30}
  lib.add(record(kDeath, 1, {10, 20, 25}));
  return lib;
}

TEST(RobustnessEvaluation, SaaPaperComparesGroupMeansAuthorsCodePairsSeeds) {
  const RunLibrary lib = library();
  // paper: the group mean {10, 20, 30} against the noise-free mean {10, 25, 40}: d = 15 (SaaRobustness
  // above).
  const RobustnessEvaluation paper =
      evaluateRobustness(lib, key(kNoise), curve({10, 20, 30}), std::nullopt, true, kPaper);
  EXPECT_TRUE(paper.saa_applies);
  EXPECT_FALSE(paper.pd_applies);
  ASSERT_TRUE(paper.saa_status.valid) << paper.saa_status.status;
  EXPECT_EQ(paper.saa.distance.value, 15.0);
  EXPECT_EQ(paper.saa_P_reference, 40.0);
  EXPECT_EQ(paper.saa_status.reference_size, 2u);
  EXPECT_EQ(paper.saa_reference, key(kBase).identity());
  EXPECT_EQ(paper.words.noise_level, 0.02);
  EXPECT_EQ(paper.pd_status.status, "the run has no population dynamics");

  // authors_code, on blocks per tick so far: seed 1, {0.01, 0.01, 0.01} against {10/1000, 30/2000, 50/3000}:
  // the diagonal (warps cost >= 1) 0 + 0.005 + 0.00667 = 0.011667; seed 2 against itself: 0; seed 3 unpaired.
  // Mean d = 0.0058333; mean normalized (sigma(-d1) - sigma(d1) + 0)/2.
  const double d1 = 0.005 + (50.0 / 3000 - 0.01);
  const RobustnessEvaluation authors =
      evaluateRobustness(lib, key(kNoise), curve({10, 20, 30}), std::nullopt, true, kAuthors);
  ASSERT_TRUE(authors.saa_status.valid) << authors.saa_status.status;
  EXPECT_NEAR(authors.saa.distance.value, d1 / 2, 1e-15);
  EXPECT_NEAR(authors.saa.normalized.value, (sigma(-d1) - sigma(d1)) / 2, 1e-15);
  EXPECT_EQ(authors.saa_status.reference_size, 2u);
  EXPECT_EQ(authors.saa_status.status,
            "ok, but seeds 3 have no reference run of the same seed (2 of 3 runs used)");
  // One run, seed 1, while going (2 samples): the reference's seed 1 cut to {10, 30}: d = 0.015 - 0.01.
  const RobustnessEvaluation live =
      evaluateRobustness(lib, key(kNoise), curve({10, 20}), 1u, false, kAuthors);
  EXPECT_NEAR(live.saa.distance.value, 0.005, 1e-15);
  // authors_code_2020: group means as paper, {10, 20, 30} against {10, 25, 40}, on (tick, blocks per tick)
  // points 1000 ticks apart: the diagonal 0 + 0.0025 + 0.0033333.
  const RobustnessEvaluation sierra =
      evaluateRobustness(lib, key(kNoise), curve({10, 20, 30}), std::nullopt, true, k2020);
  ASSERT_TRUE(sierra.saa_status.valid) << sierra.saa_status.status;
  EXPECT_NEAR(sierra.saa.distance.value, 0.0025 + 10.0 / 3000, 1e-15);
  EXPECT_EQ(sierra.saa_status.reference_size, 2u);
  EXPECT_EQ(live.T, 2000.0);
  const RobustnessEvaluation lone =
      evaluateRobustness(lib, key(kNoise), curve({10, 20, 30}), 3u, true, kAuthors);
  EXPECT_FALSE(lone.saa_status.valid);
  EXPECT_TRUE(contains(lone.saa_status.status, "no reference run has the seed")) << lone.saa_status.status;
}

TEST(RobustnessEvaluation, PdReferencesPaperWithoutPdAuthorsCodeTheLowestRates) {
  const RunLibrary lib = library();
  // paper: P = 30 against the run without PD, P_ref = 40, T = 3000; theta = 30 - (3000 - T_bar)/3000 * 40.
  const RobustnessEvaluation paper =
      evaluateRobustness(lib, key(kPd2), curve({10, 20, 30}), std::nullopt, true, kPaper);
  ASSERT_TRUE(paper.pd_applies);
  // kPd2's rates are twice kPd1's: mu - lambda = 2.8e-3, T_bar = 1/2.8e-3 - 1/5e-3 = 357.142857... - 200.
  const double t_bar = 1 / 2.8e-3 - 200;
  ASSERT_TRUE(paper.pd_status.valid) << paper.pd_status.status;
  EXPECT_NEAR(paper.pd.time_out.value, t_bar, 1e-9);
  EXPECT_EQ(paper.P_reference, 40.0);
  EXPECT_NEAR(paper.pd.theta.value, 30 - (3000 - t_bar) / 3000 * 40, 1e-9);
  EXPECT_EQ(paper.pd_reference, key(kBase).identity());

  // authors_code: reference = kPd1 (the lowest rates of the batch; kDeath has other non-zero rates).
  //   W0 = 1/1.4e-3, W = 1/2.8e-3: weight 2. On blocks per tick (over T = 3000): seed 1: (24 - 2 * 40)/3000 =
  //   -56/3000; seed 2: (36 - 2 * 20)/3000 = -4/3000; mean -30/3000 = -0.01.
  const RobustnessEvaluation authors =
      evaluateRobustness(lib, key(kPd2), curve({10, 20, 30}), std::nullopt, true, kAuthors);
  ASSERT_TRUE(authors.pd_status.valid) << authors.pd_status.status;
  EXPECT_EQ(authors.pd_reference, key(kPd1).identity());
  EXPECT_NEAR(authors.pd.weight, 2.0, 1e-12);
  EXPECT_NEAR(authors.pd.theta.value, -0.01, 1e-15);
  const double t1 = -56.0 / 3000, t2 = -4.0 / 3000;
  EXPECT_NEAR(authors.pd.normalized.value, ((sigma(t1) - sigma(-t1)) + (sigma(t2) - sigma(-t2))) / 2, 1e-15);
  EXPECT_EQ(authors.P_reference, 30.0);  // (40 + 20) / 2
  // The lowest-rate group is its own reference: theta = 0 for each seed.
  EXPECT_NEAR(
      evaluateRobustness(lib, key(kPd1), curve({10, 20, 30}), std::nullopt, true, kAuthors).pd.theta.value,
      0.0, 1e-12);

  // Pure death: no number under paper (no steady state); authors_code: W0 = W = T, theta = 25 - 25 = 0.
  const RobustnessEvaluation death =
      evaluateRobustness(lib, key(kDeath), curve({10, 20, 25}), 1u, true, kPaper);
  EXPECT_FALSE(death.pd_status.valid);
  EXPECT_TRUE(contains(death.pd_status.status, "no steady state")) << death.pd_status.status;
  EXPECT_EQ(evaluateRobustness(lib, key(kDeath), curve({10, 20, 25}), 1u, true, kAuthors).pd.theta.value,
            0.0);
  // authors_code_2020: the paper's reference (P_ideal = 40); pure death gives theta = P = 25.
  const RobustnessEvaluation sierra_death =
      evaluateRobustness(lib, key(kDeath), curve({10, 20, 25}), 1u, true, k2020);
  ASSERT_TRUE(sierra_death.pd_status.valid) << sierra_death.pd_status.status;
  EXPECT_EQ(sierra_death.pd_reference, key(kBase).identity());
  EXPECT_EQ(sierra_death.pd.theta.value, 25.0);
  EXPECT_EQ(sierra_death.pd.time_out.value, 3000.0);
  const RobustnessEvaluation sierra =
      evaluateRobustness(lib, key(kPd2), curve({10, 20, 30}), std::nullopt, true, k2020);
  EXPECT_NEAR(sierra.pd.theta.value, paper.pd.theta.value, 1e-12);  // a stable queue: the paper's value

  // A reference that is not in the library is named.
  RunLibrary without;
  without.add(record(kPd1, 1, {10, 20, 40}));
  const RobustnessEvaluation missing =
      evaluateRobustness(without, key(kPd1), curve({10, 20, 40}), 1u, true, kPaper);
  EXPECT_FALSE(missing.pd_status.valid);
  EXPECT_TRUE(
      contains(missing.pd_status.status, "no run without population dynamics #" + key(kBase).identity()))
      << missing.pd_status.status;
  EXPECT_TRUE(missing.pd.time_out.valid);  // T_bar is still known
}

TEST(RobustnessEvaluation, TablesHaveARowPerMeasureOfEveryNoisyOrPdGroupAndRun) {
  const MetricTables t = metricTables(library(), kPaper);
  std::istringstream groups(t.robustness), runs(t.robustness_runs);
  std::string line;
  std::vector<std::string> g, r;
  while (std::getline(groups, line)) g.push_back(line);
  while (std::getline(runs, line)) r.push_back(line);
  ASSERT_FALSE(g.empty());
  EXPECT_EQ(
      g[0],
      "controller,arena,waveform,beta,environment,N,runs,measure,noise,noise_level,death,birth,malfunction,"
      "repair,max_size,T,T_bar,time_out_queue,time_out_measured,out_queue,out_measured,outages,queue_differs,"
      "P,"
      "P_reference,value,normalized,valid,status,reference,reference_runs,sample_interval,identity");
  EXPECT_TRUE(contains(r[0], ",N,seed,measure,"));
  EXPECT_EQ(g.size(), 1u + 4u);  // noise (saa), pd1, pd2, death (pd); the noise-free group has none
  EXPECT_EQ(r.size(), 1u + 3u + 2u + 2u + 1u);
  bool saa = false;
  for (const std::string& row : g)
    if (contains(row, ",saa,")) {
      saa = true;
      EXPECT_TRUE(contains(row, ",15,")) << row;  // d
      EXPECT_TRUE(contains(row, ",1,\"ok\"," + key(kBase).identity() + ",2,1000," + key(kNoise).identity()))
          << row;
    }
  EXPECT_TRUE(saa);
  // Records without population records: the queue's prediction, nothing measured. kPd1: lambda 1.1e-3,
  // mu 2.5e-3: W = 1/1.4e-3 = 714.28..., L = 1.1/1.4 = 0.7857...
  const std::string pd1 =
      "," + numberText(1 / 1.4e-3, true) + ",," + numberText(1.1e-3 / 1.4e-3, true) + ",,,,";
  bool queue = false;
  for (const std::string& row : g)
    if (contains(row, key(kPd1).identity())) {
      queue = true;
      EXPECT_TRUE(contains(row, pd1)) << row << "\n" << pd1;
    }
  EXPECT_TRUE(queue);
  // The pure-death group under paper is a problem, said so.
  bool death = false;
  for (const std::string& p : t.problems) death = death || contains(p, "PD robustness: no steady state");
  EXPECT_TRUE(death);
}

TEST(RobustnessEvaluation, TablesPublishTheMeasuredOutagesBesideTheQueue) {
  // kPd1 (W = 714.28..., L = 0.7857...): seed 1 measured 3000 ticks with 1500 robot-ticks out and 2 outages
  // of 700 ticks summed; seed 2 3000 ticks, 3900 robot-ticks out, 3 outages of 3300 ticks summed.
  const MetricTables t =
      metricTables(library(OutOfSwarm{3000, 1500, 2, 700, 1}, OutOfSwarm{3000, 3900, 3, 3300, 0}), kPaper);
  const auto rows = [](const std::string& table, const std::string& identity) {
    std::istringstream in(table);
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);)
      if (contains(line, identity)) out.push_back(line);
    return out;
  };
  const auto n = [](double v) { return numberText(v, true); };
  const std::string w = n(1 / 1.4e-3), l = n(1.1e-3 / 1.4e-3);
  // The group: (700 + 3300)/5 = 800 ticks (12 % off W), (1500 + 3900)/6000 = 0.9 robots (15 % off L): 0.
  const std::vector<std::string> group = rows(t.robustness, key(kPd1).identity());
  ASSERT_EQ(group.size(), 1u);
  EXPECT_TRUE(contains(group[0], "," + w + ",800," + l + "," + n(5400.0 / 6000) + ",5,0,")) << group[0];
  // Seed 1: 350 ticks (51 % off), 0.5 robots (36 % off): flagged; seed 2: 1100 ticks (54 % off): flagged.
  const std::vector<std::string> seeds = rows(t.robustness_runs, key(kPd1).identity());
  ASSERT_EQ(seeds.size(), 2u);
  EXPECT_TRUE(contains(seeds[0], ",4,1,pd,")) << seeds[0];
  EXPECT_TRUE(contains(seeds[0], "," + w + ",350," + l + ",0.5,2,1,")) << seeds[0];
  EXPECT_TRUE(contains(seeds[1], "," + w + ",1100," + l + "," + n(3900.0 / 3000) + ",3,1,")) << seeds[1];
  // Pure death: no steady state, so no prediction; nothing measured either (no record): empty fields.
  const std::vector<std::string> death = rows(t.robustness, key(kDeath).identity());
  ASSERT_EQ(death.size(), 1u);
  EXPECT_TRUE(contains(death[0], ",,,,,,")) << death[0];
}

}  // namespace
}  // namespace swarm_forage
