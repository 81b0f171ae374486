// The bootstrap over seeds (core/metrics/bootstrap): reproducible for a seed, draw 0 as measured, each
// draw's e recomputed from that draw's resampled groups, and percentile intervals that contain the true
// mean at about the nominal rate on groups of known distribution.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/bootstrap.hpp"
#include "swarm_forage/core/util/rng.hpp"

namespace swarm_forage {
namespace {

RunKey key(uint32_t n, const std::string& controller = "crw") {
  return RunKey{controller, "32x16", n, {}, {}};
}
/// A single-sample run of N robots delivering P blocks.
RunRecord simple(const RunKey& k, uint32_t seed, double P) {
  return RunRecord{k, seed, "test", RunSeries{k.swarm_size, 1000, {P}, {P}, {0}, {1}}};
}

/// The rows of bootstrap.csv as columns by name.
std::vector<std::vector<std::string>> parse(const std::string& csv) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cellText;
    bool quoted = false;
    for (char c : line) {
      if (c == '"')
        quoted = !quoted;
      else if (c == ',' && !quoted)
        cells.push_back(cellText), cellText.clear();
      else
        cellText += c;
    }
    cells.push_back(cellText);
    rows.push_back(cells);
  }
  return rows;
}
enum Column { kDraw = 0, kN = 6, kRuns = 7, kP = 8, kE = 9, kZ = 10, kR = 11, kA = 12 };

/// The 2.5 % and 97.5 % percentiles (linear interpolation) of the draws 1 ... B of P of size `n`.
std::pair<double, double> percentileInterval(const std::string& csv, uint32_t n) {
  std::vector<double> draws;
  for (const auto& r : parse(csv))
    if (r[kDraw] != "0" && std::stoul(r[kN]) == n) draws.push_back(std::stod(r[kP]));
  std::sort(draws.begin(), draws.end());
  const auto at = [&](double q) {
    const double pos = q * (draws.size() - 1);
    const std::size_t lo = static_cast<std::size_t>(pos);
    const std::size_t hi = std::min(lo + 1, draws.size() - 1);
    return draws[lo] + (draws[hi] - draws[lo]) * (pos - lo);
  };
  return {at(0.025), at(0.975)};
}

TEST(Bootstrap, ReproducibleForASeedAndDifferentForAnother) {
  RunLibrary lib;
  for (uint32_t s = 1; s <= 5; ++s) {
    lib.add(simple(key(4), s, 10.0 * s));
    lib.add(simple(key(8), s, 15.0 * s + 3));
  }
  const std::string a = bootstrapCsv(lib, Definitions::kPaper, std::nullopt, {50, 7});
  EXPECT_EQ(a, bootstrapCsv(lib, Definitions::kPaper, std::nullopt, {50, 7}));
  EXPECT_NE(a, bootstrapCsv(lib, Definitions::kPaper, std::nullopt, {50, 8}));
  EXPECT_EQ(parse(a).size(), 51u * 2u);
}

TEST(Bootstrap, DrawZeroIsAsMeasuredAndEachDrawRecomputesEFromItsOwnGroups) {
  RunLibrary lib;
  const std::vector<double> p4{10, 20, 60}, p8{12, 50, 100};
  for (uint32_t s = 1; s <= 3; ++s) {
    lib.add(simple(key(4), s, p4[s - 1]));
    lib.add(simple(key(8), s, p8[s - 1]));
  }
  const auto rows = parse(bootstrapCsv(lib, Definitions::kPaper, std::nullopt, {200, 1}));
  std::vector<double> P4(201), P8(201), E8(201);
  for (const auto& r : rows) {
    const std::size_t d = std::stoul(r[kDraw]);
    EXPECT_EQ(r[kRuns], "3");
    EXPECT_EQ(r[kR], "");  // ideal groups: no reactivity
    EXPECT_EQ(r[kA], "");
    if (r[kN] == "4") {
      P4[d] = std::stod(r[kP]);
      EXPECT_EQ(r[kE], "");  // the smallest N has no e
    } else {
      P8[d] = std::stod(r[kP]);
      E8[d] = std::stod(r[kE]);
    }
  }
  EXPECT_DOUBLE_EQ(P4[0], 30.0);  // (10 + 20 + 60) / 3
  EXPECT_DOUBLE_EQ(P8[0], 54.0);  // (12 + 50 + 100) / 3
  int differ = 0;
  for (std::size_t d = 0; d <= 200; ++d) {
    // Each draw's mean is a mean of three of the seeds' values, and e (paper Eq 2, N1 = 4, N2 = 8) follows
    // it.
    const double phi = P8[d] / (2.0 * P4[d]);
    EXPECT_NEAR(E8[d], (1.0 / phi - 0.25) / 0.75, 1e-12) << "draw " << d;
    differ += P4[d] != P4[0];
  }
  EXPECT_GT(differ, 150);  // resampled: 3 of 27 draws of three seeds give the measured mean
}

TEST(Bootstrap, PercentileIntervalsContainTheTrueMeanAtAboutTheNominalRate) {
  // 200 synthetic groups of 20 runs, final P ~ Normal(100, 20) and Exponential(mean 50): the percentile
  // interval of the mean covers the true mean in about 95 % of them (the percentile bootstrap runs a little
  // under nominal at n = 20: a few percent, which the band allows).
  for (const bool skewed : {false, true}) {
    const double truth = skewed ? 50.0 : 100.0;
    int covered = 0;
    const int trials = 200;
    for (int t = 0; t < trials; ++t) {
      CounterRng rng(99, RngStream::kController, static_cast<uint64_t>(t), skewed ? 1 : 0);
      RunLibrary lib;
      for (uint32_t s = 1; s <= 20; ++s) {
        const double v = skewed ? -50.0 * std::log(1.0 - rng.uniform()) : 100.0 + 20.0 * rng.gaussian();
        lib.add(simple(key(16), s, v));
      }
      const auto [lo, hi] = percentileInterval(
          bootstrapCsv(lib, Definitions::kPaper, std::nullopt, {400, static_cast<uint64_t>(t + 1)}), 16);
      covered += lo <= truth && truth <= hi;
    }
    const double rate = static_cast<double>(covered) / trials;
    EXPECT_GE(rate, skewed ? 0.86 : 0.89) << (skewed ? "exponential" : "normal");
    EXPECT_LE(rate, 0.99) << (skewed ? "exponential" : "normal");
  }
}

}  // namespace
}  // namespace swarm_forage
