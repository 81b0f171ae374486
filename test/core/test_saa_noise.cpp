// Sensor and actuator noise (core/world/saa_noise.hpp): the perturbations measured over a run match the
// configured model within sampling error; noise off changes nothing; the draws do not depend on threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

#include "sharing_pool.hpp"
#include "swarm_forage/core/run/simulation.hpp"
#include "swarm_forage/core/util/geometry.hpp"

namespace swarm_forage {
namespace {

struct Moments {
  double n = 0, sum = 0, sum2 = 0, max_abs = 0;
  void add(double d) {
    ++n;
    sum += d;
    sum2 += d * d;
    max_abs = std::max(max_abs, std::abs(d));
  }
  double mean() const { return sum / n; }
  double sd() const { return std::sqrt((sum2 - sum * sum / n) / (n - 1)); }
};

/// The sample mean and sigma of `d` against the model: five standard errors (the mean's sigma / sqrt(n);
/// the sample sigma's, at most sigma / sqrt(2 n) for these two models).
void expectModel(const Moments& m, const DeviceNoise& d, const char* what) {
  SCOPED_TRACE(what);
  ASSERT_GT(m.n, 1000);
  const double sigma = d.model == NoiseModel::kGaussian ? d.level : d.level / std::sqrt(3.0);
  std::printf("%-9s %s: n %.0f, mean %+.2e, sigma %.5f (model %.5f)\n", what, d.word().c_str(), m.n, m.mean(),
              m.sd(), sigma);
  EXPECT_NEAR(m.mean(), 0.0, 5 * sigma / std::sqrt(m.n));
  EXPECT_NEAR(m.sd(), sigma, 5 * sigma / std::sqrt(2 * m.n));
  if (d.model == NoiseModel::kUniform) {
    EXPECT_LE(m.max_abs, d.level * (1 + 1e-6));
  }
}

WorldConfig noisyWorld(const SaaNoise& noise, uint32_t n_robots = 64) {
  WorldConfig c;
  c.n_robots = n_robots;
  c.seed = 7;
  c.noise = noise;
  return c;
}

/// Runs `ticks` ticks of CRW and hands each tick's truth and perception to `see`.
void run(const WorldConfig& c, int ticks,
         const std::function<void(const SensorData&, const SensorData&)>& see) {
  Simulation sim(c, "crw");
  for (int t = 0; t < ticks; ++t) {
    sim.step();
    see(sim.sensors(), sim.world().perceived(sim.sensors()));
  }
}

TEST(SaaNoise, SensorPerturbationsMatchTheModel) {
  for (const NoiseModel model : {NoiseModel::kGaussian, NoiseModel::kUniform}) {
    SaaNoise noise;
    noise.proximity = {model, 0.01};
    noise.light = {model, 0.2};
    noise.position = {model, 0.05};
    noise.heading = {model, 0.1};
    Moments prox, light, pos, heading;
    // A crowd (512 robots in 32 x 16 m), so that proximity readings are frequent enough to measure.
    run(noisyWorld(noise, 512), 300, [&](const SensorData& truth, const SensorData& seen) {
      ASSERT_NE(&truth, &seen);
      for (std::size_t i = 0; i < truth.size(); ++i) {
        EXPECT_EQ(seen.threatened[i], truth.threatened[i]);  // a reading is perturbed, none is invented
        if (truth.threatened[i]) {
          prox.add(double(seen.obstacle_x[i]) - truth.obstacle_x[i]);
          prox.add(double(seen.obstacle_y[i]) - truth.obstacle_y[i]);
        } else {
          EXPECT_EQ(seen.obstacle_x[i], truth.obstacle_x[i]);
        }
        light.add(double(seen.light_x[i]) - truth.light_x[i]);
        light.add(double(seen.light_y[i]) - truth.light_y[i]);
        pos.add(double(seen.x[i]) - truth.x[i]);
        pos.add(double(seen.y[i]) - truth.y[i]);
        heading.add(wrapAngle(double(seen.theta[i]) - truth.theta[i]));
        EXPECT_EQ(seen.ground[i], truth.ground[i]);  // no ground noise asked
      }
    });
    expectModel(prox, noise.proximity, "proximity");
    expectModel(light, noise.light, "light");
    expectModel(pos, noise.position, "position");
    expectModel(heading, noise.heading, "heading");
  }
}

TEST(SaaNoise, GroundMisreadsAtTheConfiguredRateAndAlwaysAsAnotherKind) {
  SaaNoise noise;
  noise.ground = 0.1;
  double reads = 0, misreads = 0;
  run(noisyWorld(noise), 300, [&](const SensorData& truth, const SensorData& seen) {
    for (std::size_t i = 0; i < truth.size(); ++i) {
      ++reads;
      if (seen.ground[i] != truth.ground[i]) ++misreads;
      EXPECT_LE(seen.ground[i], kBlockGround);  // no cache in this arena: no cache ground
    }
  });
  const double p = noise.ground;
  EXPECT_NEAR(misreads / reads, p, 5 * std::sqrt(p * (1 - p) / reads));  // binomial: five standard errors
}

TEST(SaaNoise, WheelGainsMatchTheModelAndStayWithinTheTopSpeed) {
  for (const NoiseModel model : {NoiseModel::kGaussian, NoiseModel::kUniform}) {
    SaaNoise noise;
    noise.wheels = {model, 0.1};
    Moments gain;
    for (uint64_t tick = 0; tick < 200; ++tick)
      for (uint32_t id = 0; id < 64; ++id) {
        float left = 0.05f, right = -0.05f;  // half the top speed: the gain is not cut off
        noise.perturbWheels(left, right, id, 7, tick, 0.1);
        gain.add(left / 0.05 - 1);
        gain.add(right / -0.05 - 1);
        float fast = 0.1f, back = -0.1f;
        noise.perturbWheels(fast, back, id, 7, tick, 0.1);
        EXPECT_LE(fast, 0.1f);
        EXPECT_GE(back, -0.1f);
      }
    expectModel(gain, noise.wheels, "wheels");
  }
}

TEST(SaaNoise, WheelNoiseMovesTheRobotsAndSensorNoiseOnlyWhatTheyBelieve) {
  const auto poses = [](const SaaNoise& noise) {
    Simulation sim(noisyWorld(noise), "crw");
    for (int t = 0; t < 50; ++t) sim.step();
    return sim.world().robots().x;
  };
  SaaNoise wheels;
  wheels.wheels.level = 0.05;
  EXPECT_NE(poses(wheels), poses(SaaNoise{}));
  // CRW steers by its proximity and light readings only when threatened or carrying: position noise,
  // which CRW never reads, leaves the bodies where they were.
  SaaNoise position;
  position.position.level = 0.05;
  EXPECT_EQ(poses(position), poses(SaaNoise{}));
}

TEST(SaaNoise, OffChangesNothing) {
  WorldConfig c = noisyWorld(SaaNoise{});
  EXPECT_FALSE(c.noise.enabled());
  EXPECT_EQ(c.describeConstants().find("noise"), std::string::npos);
  Simulation sim(c, "crw");
  sim.step();
  EXPECT_EQ(&sim.world().perceived(sim.sensors()), &sim.sensors());
}

TEST(SaaNoise, WordsNameTheDevicesWithNoise) {
  SaaNoise n;
  n.proximity = {NoiseModel::kGaussian, 0.01};
  n.light = {NoiseModel::kUniform, 0.02};
  n.ground = 0.05;
  n.wheels = {NoiseModel::kGaussian, 0.01};
  EXPECT_EQ(
      n.describe(),
      "noise/proximity=gaussian:0.01 noise/light=uniform:0.02 noise/ground=0.05 noise/wheels=gaussian:0.01");
  WorldConfig c;
  c.noise = n;
  const std::string words = c.describeConstants();
  EXPECT_EQ(words.substr(words.size() - n.describe().size()), n.describe());
}

TEST(SaaNoise, OneDeviceDoesNotChangeAnothersDraws) {
  SaaNoise light_only, both;
  light_only.light.level = 0.1;
  both = light_only;
  both.position.level = 0.1;
  std::vector<float> a, b;
  run(noisyWorld(light_only), 20,
      [&](const SensorData&, const SensorData& s) { a.insert(a.end(), s.light_x.begin(), s.light_x.end()); });
  run(noisyWorld(both), 20,
      [&](const SensorData&, const SensorData& s) { b.insert(b.end(), s.light_x.begin(), s.light_x.end()); });
  EXPECT_EQ(a, b);  // position noise is never read by CRW: same bodies, same light draws
}

TEST(SaaNoise, ThreadCountsGiveIdenticalRuns) {
  SaaNoise noise;
  for (std::size_t k = 0; k < SaaNoise::deviceNames().size(); ++k)
    noise.device(static_cast<NoisyDevice>(k)) = {NoiseModel::kGaussian, 0.02};
  noise.ground = 0.02;
  for (const char* kind : {"crw", "dpo", "gp_dpo"}) {
    SCOPED_TRACE(kind);
    WorldConfig c = noisyWorld(noise);
    c.n_robots = 2500;  // more than two sensing chunks: the threads split the robots
    std::vector<std::unique_ptr<Simulation>> runs;
    for (unsigned threads : {1u, 2u, 3u})
      runs.push_back(std::make_unique<Simulation>(c, kind, ControllerConfigs{}, sharingPool(threads)));
    for (int t = 0; t < 30; ++t)
      for (auto& r : runs) r->step();
    for (std::size_t k = 1; k < runs.size(); ++k) {
      EXPECT_EQ(runs[k]->world().robots().x, runs[0]->world().robots().x);
      EXPECT_EQ(runs[k]->world().robots().theta, runs[0]->world().robots().theta);
      EXPECT_EQ(runs[k]->world().perceived(runs[k]->sensors()).x,
                runs[0]->world().perceived(runs[0]->sensors()).x);
    }
  }
}

TEST(SaaNoise, BadLevelsAreRefusedNamingTheParameterAndRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const double bad : {-0.01, nan, inf, 11.0}) {
    SaaNoise n;
    n.light.level = bad;
    try {
      n.validate();
      ADD_FAILURE() << "accepted light level " << bad;
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find("noise/light/level must be a number in [0, 10]"),
                std::string::npos)
          << e.what();
    }
  }
  for (const double bad : {-0.1, 1.5, nan}) {
    SaaNoise n;
    n.ground = bad;
    EXPECT_THROW(n.validate(), ParameterError);
  }
  SaaNoise wheels;
  wheels.wheels.level = 1.5;
  EXPECT_THROW(wheels.validate(), ParameterError);
  WorldConfig c;
  c.noise.heading.level = -1;
  EXPECT_THROW(World{c}, ParameterError);
}

}  // namespace
}  // namespace swarm_forage
