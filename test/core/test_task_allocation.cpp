// GP-DPO's task-allocation arithmetic against hand-computed values, and the abort test without exp
// (aborts()) against the probability itself, near its boundary too.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "swarm_forage/core/controllers/task_allocation.hpp"

namespace swarm_forage {
namespace {

TEST(TaskAllocation, PartitionProbability) {
  // E_g = 30000 > E_h + E_c = 20000: theta = 6 (30000 / 20000 - 1) = 3; 1 / (1 + e^-3) = 0.9525741268.
  EXPECT_NEAR(partitionTheta(30000, 10000, 10000, 6), 3.0, 1e-12);
  EXPECT_NEAR(partitionProbability(30000, 10000, 10000, 6), 0.9525741268, 1e-10);
  // E_g = 10000 <= 12000: theta = 4 (1 - 12000 / 10000) = -0.8; 1 / (1 + e^0.8) = 0.3100255189.
  EXPECT_NEAR(partitionTheta(10000, 8000, 4000, 4), -0.8, 1e-12);
  EXPECT_NEAR(partitionProbability(10000, 8000, 4000, 4), 0.3100255189, 1e-10);
  // Equal: theta = 6 (1 - 1) = 0 -> 0.5; no information (zero estimates) -> 0.5.
  EXPECT_DOUBLE_EQ(partitionProbability(20000, 12000, 8000, 6), 0.5);
  EXPECT_DOUBLE_EQ(partitionProbability(0, 0, 0, 6), 0.5);
}

TEST(TaskAllocation, SubtaskSwitchProbability) {
  // Harvester -> collector with E_c = 16000 > E_h = 10000: 8 (10000/16000 - 1.25) = 8 (-0.625) = -5;
  // logistic(-5) = 0.0066928509.
  EXPECT_NEAR(subtaskSwitchProbability(10000, 16000), 0.0066928509, 1e-10);
  // Collector -> harvester with E_h = 10000 < E_c = 16000: 8 (1 - 1.25) = -2; logistic(-2) = 0.1192029220.
  EXPECT_NEAR(subtaskSwitchProbability(16000, 10000), 0.1192029220, 1e-10);
  EXPECT_NEAR(subtaskSwitchProbability(5000, 5000), 0.1192029220, 1e-10);
  EXPECT_DOUBLE_EQ(subtaskSwitchProbability(0, 5000), 0.5);  // no estimate
  EXPECT_DOUBLE_EQ(subtaskSwitchProbability(5000, 0), 0.5);
}

TEST(TaskAllocation, AbortProbability) {
  // t = 3000, E = 1000: |3 - 3| = 0 -> 1 / (1 + e^0) = 0.5.
  EXPECT_DOUBLE_EQ(abortProbability(3000, 1000), 0.5);
  // t = 2000, E = 1000: |2 - 3| = 1 -> 1 / (1 + e^8) = 1 / 2981.958 = 3.3535013047e-4.
  EXPECT_NEAR(abortProbability(2000, 1000), 3.3535013047e-4, 1e-14);
  // t = 5000, E = 2000: |2.5 - 3| = 0.5 -> 1 / (1 + e^4) = 0.0179862100.
  EXPECT_NEAR(abortProbability(5000, 2000), 0.0179862100, 1e-10);
  // t = 0: 1 / (1 + e^24) = 3.7751345441e-11; symmetric around 3E: t = 4000, E = 1000 as t = 2000.
  EXPECT_NEAR(abortProbability(0, 1000), 3.7751345441e-11, 1e-20);
  EXPECT_DOUBLE_EQ(abortProbability(4000, 1000), abortProbability(2000, 1000));
  EXPECT_DOUBLE_EQ(abortProbability(10, 0), 0.0);
}

TEST(TaskAllocation, EmaUpdate) {
  // 0.2 x 20000 + 0.8 x 10000 = 4000 + 8000 = 12000.
  EXPECT_DOUBLE_EQ(emaUpdate(20000, 10000), 12000.0);
  // 0.2 x 1500 + 0.8 x 3000 = 300 + 2400 = 2700.
  EXPECT_DOUBLE_EQ(emaUpdate(1500, 3000), 2700.0);
  EXPECT_DOUBLE_EQ(emaUpdate(1500, 3000, 0.0), 1500.0);
}

TEST(TaskAllocation, AbortsIsTheProbabilityAboveTheDraw) {
  std::mt19937_64 gen(25);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double reactivities[] = {0.0, 0.5, 8.0, 40.0, -1.0};
  for (int k = 0; k < 200000; ++k) {
    const double estimate = k % 97 == 0 ? 0.0 : 1.0 + 40000 * unit(gen);
    const double t = std::floor(5 * estimate * unit(gen)), r = reactivities[k % 5], offset = 4 * unit(gen);
    const double p = abortProbability(t, estimate, r, offset);
    // Draws at the probability, one step either side of it, and anywhere.
    for (double u : {p, std::nextafter(p, 0.0), std::nextafter(p, 1.0), unit(gen), 0.5 * unit(gen)})
      ASSERT_EQ(aborts(u, t, estimate, r, offset), p > u) << "t " << t << " E " << estimate << " u " << u;
  }
}

}  // namespace
}  // namespace swarm_forage
