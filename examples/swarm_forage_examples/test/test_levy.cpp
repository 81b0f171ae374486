// The Levy walker's batch on its own: its step lengths follow the truncated power law, its commands do
// not depend on how the robot range is split, its constants are validated and its YAML holds the defaults.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/config.hpp"
#include "swarm_forage_examples/levy.hpp"

namespace swarm_forage_examples {
namespace {

using namespace swarm_forage;

double powerLawCdf(double l, const LevyConfig& c) {
  const double e = 1.0 - c.mu;
  return (std::pow(l, e) - std::pow(c.l_min, e)) / (std::pow(c.l_max, e) - std::pow(c.l_min, e));
}

// Kolmogorov-Smirnov statistic of `sample` against the truncated power law.
double ksDistance(std::vector<double> sample, const LevyConfig& c) {
  std::sort(sample.begin(), sample.end());
  const double n = static_cast<double>(sample.size());
  double d = 0;
  for (std::size_t k = 0; k < sample.size(); ++k) {
    const double f = powerLawCdf(sample[k], c);
    d = std::max({d, f - k / n, (k + 1) / n - f});
  }
  return d;
}

// An open floor without walls or blocks, robots moving as the wheels say (axle 0.14 m, 5 ticks/s).
struct OpenFloor {
  SensorData s;
  explicit OpenFloor(uint32_t n) {
    s.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
      s.x[i] = 0.5f * i;
      s.ground[i] = kFloor;
      s.carried_block[i] = -1;
    }
  }
  void move(const CommandData& c) {
    for (uint32_t k = 0; k < c.size(); ++k) {
      const uint32_t i = c.first_id + k;
      const double v = 0.5 * (c.left[k] + c.right[k]), w = (c.right[k] - c.left[k]) / 0.14;
      s.x[i] += static_cast<float>(0.2 * v * std::cos(s.theta[i]));
      s.y[i] += static_cast<float>(0.2 * v * std::sin(s.theta[i]));
      s.theta[i] = static_cast<float>(wrapAngle(s.theta[i] + 0.2 * w));
    }
  }
};

TEST(Levy, InverseCdfDrawsFollowTheTruncatedPowerLaw) {
  for (double mu : {1.1, 1.5, 2.0, 2.5, 3.0}) {
    LevyConfig c;
    c.mu = mu;
    std::vector<double> lengths;
    for (uint64_t k = 0; k < 20000; ++k) {
      CounterRng rng(7, RngStream::kController, k, 0);
      lengths.push_back(levyStepLength(rng.uniform(), c.mu, c.l_min, c.l_max));
    }
    EXPECT_GE(*std::min_element(lengths.begin(), lengths.end()), c.l_min);
    EXPECT_LE(*std::max_element(lengths.begin(), lengths.end()), c.l_max);
    // 1.63 / sqrt(n): the 1 % critical value; a fixed seed makes the test deterministic.
    EXPECT_LT(ksDistance(lengths, c), 1.63 / std::sqrt(lengths.size())) << "mu " << mu;
    c.mu = mu + 0.3;  // the test can fail: another exponent is told apart
    if (c.mu <= 3) {
      EXPECT_GT(ksDistance(lengths, c), 1.63 / std::sqrt(lengths.size())) << "mu " << mu;
    }
  }
  EXPECT_DOUBLE_EQ(levyStepLength(0.0, 2.0, 0.2, 32.0), 0.2);
  EXPECT_NEAR(levyStepLength(1.0, 2.0, 0.2, 32.0), 32.0, 1e-9);
}

TEST(Levy, RobotsOnAnOpenFloorWalkStepsOfTheDrawnLengths) {
  const LevyConfig c;
  const uint32_t n = 40;
  LevyBatch batch(c, CrwConfig{}, 3, 0, n);
  OpenFloor floor(n);
  CommandData out;
  ControllerStatus status;
  std::vector<double> drawn, current(n, 0.0), walked(n, 0.0);
  std::vector<uint64_t> seen(n, 0);
  for (uint64_t tick = 0; tick < 6000; ++tick) {
    std::vector<float> x = floor.s.x, y = floor.s.y;
    batch.step(tick, floor.s, out, status);
    for (uint32_t i = 0; i < n; ++i) {
      if (batch.stepsStarted(i) != seen[i]) {
        // The step just ended was walked in full, overshooting by at most one tick's travel.
        if (seen[i] > 0) {
          EXPECT_GE(walked[i], current[i] - 1e-4);
          EXPECT_LE(walked[i], current[i] + 0.2 * c.step_force * 0.01 + 1e-4);
        }
        current[i] = batch.lastStepLength(i);
        drawn.push_back(current[i]);
        seen[i] = batch.stepsStarted(i);
        walked[i] = 0;
      }
    }
    floor.move(out);
    for (uint32_t i = 0; i < n; ++i) walked[i] += std::hypot(floor.s.x[i] - x[i], floor.s.y[i] - y[i]);
    EXPECT_EQ(status.state_counts[0], n);  // all explore
    EXPECT_EQ(status.in_avoidance, 0u);
  }
  ASSERT_GT(drawn.size(), 1500u);
  EXPECT_LT(ksDistance(drawn, c), 1.63 / std::sqrt(drawn.size()));
}

// Sensor readings that visit every state: blocks, the nest, threats, pick-ups and drops done.
void varySensors(SensorData& s, uint64_t tick) {
  for (uint32_t i = 0; i < s.size(); ++i) {
    CounterRng rng(99, RngStream::kPlacement, i, tick);
    s.x[i] = static_cast<float>(rng.uniform(0, 32));
    s.y[i] = static_cast<float>(rng.uniform(0, 16));
    s.theta[i] = static_cast<float>(rng.uniform(-kPi, kPi));
    s.threatened[i] = rng.uniform() < 0.2;
    s.obstacle_x[i] = 0.05f;
    s.obstacle_y[i] = static_cast<float>(rng.uniform(-0.1, 0.1));
    s.light_x[i] = static_cast<float>(rng.uniform(-1, 1));
    s.light_y[i] = 0.3f;
    const uint64_t phase = (tick / 60 + i) % 4;  // explore, find a block, carry home, leave
    s.ground[i] = phase == 1 ? kBlockGround : phase == 3 ? kNest : kFloor;
    s.carried_block[i] = phase >= 2 && (phase == 2 || tick % 60 < 40) ? 5 : -1;
    s.events[i] = phase == 2 && tick % 60 == 0 ? kPickupDone : phase == 3 && tick % 60 == 40 ? kDropDone : 0;
  }
}

TEST(Levy, SameCommandsForAnySplitOfTheRobotRange) {
  const uint32_t n = 37;
  const std::vector<std::vector<uint32_t>> splits = {{0, n}, {0, 13, n}, {0, 1, 2, 20, 36, n}};
  std::vector<std::vector<std::unique_ptr<LevyBatch>>> batches(splits.size());
  for (std::size_t k = 0; k < splits.size(); ++k)
    for (std::size_t p = 0; p + 1 < splits[k].size(); ++p)
      batches[k].push_back(std::make_unique<LevyBatch>(LevyConfig{}, CrwConfig{}, 11, splits[k][p],
                                                       splits[k][p + 1] - splits[k][p]));
  SensorData s;
  s.resize(n);
  std::vector<uint32_t> visited(static_cast<std::size_t>(LevyState::kCount), 0);
  for (uint64_t tick = 0; tick < 1200; ++tick) {
    varySensors(s, tick);
    std::vector<std::vector<float>> left(splits.size()), right(splits.size());
    std::vector<std::vector<uint8_t>> request(splits.size());
    std::vector<std::vector<uint32_t>> counts(splits.size());
    std::vector<uint32_t> avoiding(splits.size(), 0);
    for (std::size_t k = 0; k < splits.size(); ++k) {
      counts[k].assign(visited.size(), 0);
      for (auto& b : batches[k]) {
        CommandData out;
        ControllerStatus status;
        b->step(tick, s, out, status);
        ASSERT_EQ(out.first_id, b->firstId());
        left[k].insert(left[k].end(), out.left.begin(), out.left.end());
        right[k].insert(right[k].end(), out.right.begin(), out.right.end());
        request[k].insert(request[k].end(), out.request.begin(), out.request.end());
        for (std::size_t st = 0; st < counts[k].size(); ++st) counts[k][st] += status.state_counts[st];
        avoiding[k] += status.in_avoidance;
        ASSERT_EQ(status.state_names.size(), visited.size());
      }
      EXPECT_EQ(left[k], left[0]) << "tick " << tick << " split " << k;
      EXPECT_EQ(right[k], right[0]) << "tick " << tick << " split " << k;
      EXPECT_EQ(request[k], request[0]) << "tick " << tick << " split " << k;
      EXPECT_EQ(counts[k], counts[0]) << "tick " << tick << " split " << k;
      EXPECT_EQ(avoiding[k], avoiding[0]);
    }
    for (std::size_t st = 0; st < visited.size(); ++st) visited[st] += counts[0][st];
  }
  for (std::size_t st = 0; st < visited.size(); ++st) EXPECT_GT(visited[st], 0u) << "state " << st;
}

TEST(Levy, RobotsOutOfTheSwarmStandStillAndNewcomersStartAfresh) {
  const uint32_t n = 8;
  LevyBatch batch(LevyConfig{}, CrwConfig{}, 5, 0, n);
  SensorData s;
  s.resize(n);
  CommandData out;
  ControllerStatus status;
  uint64_t tick = 0;
  for (; tick < 100; ++tick) {
    varySensors(s, tick);
    batch.step(tick, s, out, status);
  }
  uint32_t r = 0;  // a robot busy with something other than exploring
  while (r < n && batch.state(r) == LevyState::kExplore) ++r;
  ASSERT_LT(r, n);
  const LevyState before = batch.state(r);
  s.active.assign(n, 1);
  s.active[r] = 0;
  for (uint64_t until = tick + 50; tick < until; ++tick) {
    varySensors(s, tick);
    batch.step(tick, s, out, status);
    EXPECT_EQ(out.left[r], 0.f);
    EXPECT_EQ(out.right[r], 0.f);
    EXPECT_EQ(out.request[r], kNone);
    EXPECT_EQ(batch.state(r), before) << "tick " << tick;
    uint32_t counted = 0;
    for (uint32_t c : status.state_counts) counted += c;
    EXPECT_EQ(counted, n - 1);
  }
  s.active[r] = 1;
  varySensors(s, tick);
  s.events[r] = kJoined;
  s.ground[r] = kFloor;
  s.carried_block[r] = -1;
  s.threatened[r] = 0;
  const uint64_t steps = batch.stepsStarted(r);
  batch.step(tick, s, out, status);
  EXPECT_EQ(batch.state(r), LevyState::kExplore);
  EXPECT_EQ(batch.stepsStarted(r), steps + 1);  // its step forgotten: a new one drawn
}

TEST(Levy, ConstantsOutOfRangeAreRefusedNamingKeyAndRange) {
  const std::string kind = kLevyKind;
  const std::vector<std::pair<std::function<void(LevyConfig&)>, std::string>> cases = {
      {[](LevyConfig& c) { c.mu = 1.0; }, "/mu must be in (1, 3]"},
      {[](LevyConfig& c) { c.mu = 3.5; }, "/mu must be in (1, 3]"},
      {[](LevyConfig& c) { c.l_min = 0; }, "/l_min must be in (0, 100] m"},
      {[](LevyConfig& c) { c.l_max = 0.1; }, "/l_max must be in (l_min, 1000] m"},
      {[](LevyConfig& c) { c.step_force = 0; }, "/step_force must be in (0, 100] cm/s"},
      {[](LevyConfig& c) { c.avoidance_force = -1; }, "/avoidance_force must be in [0, 100] cm/s"},
  };
  for (const auto& [change, message] : cases) {
    LevyConfig c;
    change(c);
    try {
      LevyBatch batch(c, CrwConfig{}, 1, 0, 1);
      ADD_FAILURE() << "accepted: " << message;
    } catch (const ParameterError& e) {
      EXPECT_EQ(std::string(e.what()), kind + message);
    }
  }
  EXPECT_NO_THROW(LevyConfig{}.validate());
}

// Sets each constant from the YAML section, as the ROS layer does from the file a launch loaded.
struct FromYaml : ConstantVisitor {
  YAML::Node section;
  std::vector<std::string> names;
  explicit FromYaml(YAML::Node s) : section(std::move(s)) {}
  void number(const char* n, double& v) override {
    names.push_back(n);
    v = section[n].as<double>();
  }
  void count(const char* n, uint32_t& v) override {
    names.push_back(n);
    v = section[n].as<uint32_t>();
  }
  void degrees(const char* n, double& radians) override {
    names.push_back(n);
    radians = deg2rad(section[n].as<double>());
  }
  void choice(const char* n, bool& flag, const char*, const char* on) override {
    names.push_back(n);
    flag = section[n].as<std::string>() == on;
  }
};

TEST(Levy, YamlHoldsExactlyTheKeysAtTheCodeDefaults) {
  const std::string file = __FILE__;  // .../test/test_levy.cpp
  const YAML::Node root = YAML::LoadFile(file.substr(0, file.rfind("/test/")) + "/config/levy.yaml");
  ASSERT_EQ(root.size(), 1u);
  const YAML::Node section = root[kLevyKind];
  ASSERT_TRUE(section.IsMap());
  LevyConfig from_file;
  FromYaml read(section);
  visitLevyParameters(from_file, read);
  std::vector<std::string> in_file;
  for (const auto& entry : section) in_file.push_back(entry.first.as<std::string>());
  EXPECT_EQ(in_file, read.names);
  // Every constant, by name and value: the file's equal the code's defaults.
  struct Values : ConstantVisitor {
    std::vector<std::pair<std::string, double>> v;
    void number(const char* n, double& x) override { v.emplace_back(n, x); }
    void count(const char* n, uint32_t& x) override { v.emplace_back(n, x); }
    void degrees(const char* n, double& x) override { v.emplace_back(n, x); }
    void choice(const char* n, bool& x, const char*, const char*) override { v.emplace_back(n, x); }
  } file_values, default_values;
  LevyConfig defaults;
  visitLevyParameters(from_file, file_values);
  visitLevyParameters(defaults, default_values);
  EXPECT_EQ(file_values.v, default_values.v);
}

}  // namespace
}  // namespace swarm_forage_examples
