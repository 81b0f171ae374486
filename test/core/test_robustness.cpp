// The robustness measures (docs/robustness-measures.md) against hand-computed cases, both definitions; the
// arithmetic is beside each number.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/robustness.hpp"
#include "swarm_forage/core/metrics/robustness_evaluation.hpp"
#include "swarm_forage/core/metrics/run_library.hpp"

namespace swarm_forage {
namespace {

using V = std::vector<double>;
constexpr auto kPaper = Definitions::kPaper;
constexpr auto kAuthors = Definitions::kAuthorsCode;
constexpr auto k2019 = Definitions::kAuthorsCode2019;

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

TEST(SaaRobustness, PaperIsDtwOnValuesAuthorsCodeOnTickValuePoints) {
  // run P = {10, 10, 30}, noise-free P = {10, 30, 30}.
  // Values only: the path (0,0) (1,0) (2,1) (2,2) costs |10-10| + |10-10| + |30-30| + |30-30| = 0.
  const SaaRobustness paper = saaRobustness(curve({10, 30, 30}), curve({10, 10, 30}), kPaper);
  ASSERT_TRUE(paper.distance.valid) << paper.distance.reason;
  EXPECT_EQ(paper.distance.value, 0.0);
  EXPECT_EQ(paper.normalized.value, 0.0);  // sigma(0) - sigma(0): the best value
  // (tick, P) points 1000 ticks apart, L1 cost: any warp step adds >= 1000, so the diagonal is optimal:
  // |10-10| + |10-30| + |30-30| = 20.
  const SaaRobustness authors = saaRobustness(curve({10, 30, 30}), curve({10, 10, 30}), kAuthors);
  ASSERT_TRUE(authors.distance.valid) << authors.distance.reason;
  EXPECT_EQ(authors.distance.value, 20.0);
  EXPECT_NEAR(authors.normalized.value, sigma(-20.0) - sigma(20.0), 1e-15);

  // run {10, 20, 30} against {10, 25, 40}: costs |x - y| row by row {0 15 30; 10 5 20; 20 5 10};
  // cumulative D: {0 15 45; 10 5 25; 30 10 15}: d = 15 (the diagonal 0 + 5 + 10).
  const SaaRobustness d15 = saaRobustness(curve({10, 25, 40}), curve({10, 20, 30}), kPaper);
  EXPECT_EQ(d15.distance.value, 15.0);
  EXPECT_NEAR(d15.normalized.value, 1.0 / (1.0 + std::exp(15.0)) - 1.0 / (1.0 + std::exp(-15.0)), 1e-15);
  EXPECT_LT(d15.normalized.value, 0.0);
  EXPECT_GT(d15.normalized.value, -1.0);
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
  EXPECT_TRUE(contains(death.reason, "authors_code takes T_bar = T under pure death")) << death.reason;
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
  const PdRobustness authors = pdRobustness(80, 100, 20000, r, rates(5e-5, 2.5e-4, 5e-4, 1e-3), kAuthors);
  ASSERT_TRUE(authors.theta.valid) << authors.theta.reason;
  EXPECT_NEAR(authors.weight, 2.0, 1e-12);
  EXPECT_NEAR(authors.theta.value, -120.0, 1e-9);
  EXPECT_NEAR(authors.normalized.value, sigma(-120.0) - sigma(120.0), 1e-15);
  // Pure death in the authors' code: W0 = W = T, theta = P - P_reference = 80 - 100.
  EXPECT_NEAR(pdRobustness(80, 100, 20000, rates(2e-4, 0, 0, 0), rates(1e-4, 0, 0, 0), kAuthors).theta.value,
              -20.0, 1e-12);
  // An unstable queue has no number, in either definition.
  const PdRobustness unstable = pdRobustness(80, 100, 20000, rates(0, 0, 3e-3, 2e-3), r, kPaper);
  EXPECT_FALSE(unstable.theta.valid);
  EXPECT_EQ(unstable.theta.value, 0.0);
  EXPECT_TRUE(contains(unstable.theta.reason, "no steady state")) << unstable.theta.reason;
  EXPECT_FALSE(pdRobustness(80, 100, 20000, r, rates(0, 0, 3e-3, 2e-3), kAuthors).theta.valid);
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

RunLibrary library() {
  RunLibrary lib;
  lib.add(record(kBase, 1, {10, 30, 50}));
  lib.add(record(kBase, 2, {10, 20, 30}));  // mean {10, 25, 40}
  lib.add(record(kNoise, 1, {10, 20, 30}));
  lib.add(record(kNoise, 2, {10, 20, 30}));
  lib.add(record(kNoise, 3, {10, 20, 30}));  // seed 3 has no noise-free partner
  lib.add(record(kPd1, 1, {10, 20, 40}));
  lib.add(record(kPd1, 2, {10, 20, 20}));  // mean {10, 20, 30}
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

  // authors_code: seed 1 against {10, 30, 50}: diagonal |0| + |20-30| + |30-50| = 30 (warps cost >= 1000);
  // seed 2 against {10, 20, 30}: 0; seed 3 unpaired. Mean d = 15; mean normalized (sigma(-30) - sigma(30) +
  // 0)/2.
  const RobustnessEvaluation authors =
      evaluateRobustness(lib, key(kNoise), curve({10, 20, 30}), std::nullopt, true, kAuthors);
  ASSERT_TRUE(authors.saa_status.valid) << authors.saa_status.status;
  EXPECT_EQ(authors.saa.distance.value, 15.0);
  EXPECT_NEAR(authors.saa.normalized.value, (sigma(-30) - sigma(30)) / 2, 1e-15);
  EXPECT_EQ(authors.saa_status.reference_size, 2u);
  EXPECT_EQ(authors.saa_status.status,
            "ok, but seeds 3 have no reference run of the same seed (2 of 3 runs used)");
  // One run, seed 1, while going (2 samples): the reference's seed 1 cut to {10, 30}: d = 10.
  const RobustnessEvaluation live =
      evaluateRobustness(lib, key(kNoise), curve({10, 20}), 1u, false, kAuthors);
  EXPECT_EQ(live.saa.distance.value, 10.0);
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
  //   W0 = 1/1.4e-3, W = 1/2.8e-3: weight 2. seed 1: 24 - 2 * 40 = -56; seed 2: 36 - 2 * 20 = -4; mean -30.
  const RobustnessEvaluation authors =
      evaluateRobustness(lib, key(kPd2), curve({10, 20, 30}), std::nullopt, true, kAuthors);
  ASSERT_TRUE(authors.pd_status.valid) << authors.pd_status.status;
  EXPECT_EQ(authors.pd_reference, key(kPd1).identity());
  EXPECT_NEAR(authors.pd.weight, 2.0, 1e-12);
  EXPECT_NEAR(authors.pd.theta.value, -30.0, 1e-9);
  EXPECT_NEAR(authors.pd.normalized.value, ((sigma(-56) - sigma(56)) + (sigma(-4) - sigma(4))) / 2, 1e-15);
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
      "repair,max_size,T,T_bar,P,P_reference,value,normalized,valid,status,reference,reference_runs,"
      "sample_interval,identity");
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
  // The pure-death group under paper is a problem, said so.
  bool death = false;
  for (const std::string& p : t.problems) death = death || contains(p, "PD robustness: no steady state");
  EXPECT_TRUE(death);
}

}  // namespace
}  // namespace swarm_forage
