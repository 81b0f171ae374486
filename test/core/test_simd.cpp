// The 4-lane AVX2 paths give the bits of the scalar ones: sine/cosine and atan2 over random and edge
// inputs, the batched wander forces, motion forces and steering, and whole runs of every controller with the
// paths on and off (core/util/simd.hpp). Skipped where the CPU has no AVX2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/forage_common.hpp"
#include "swarm_forage/core/run/simulation.hpp"
#include "swarm_forage/core/util/fast_math_x4.hpp"
#include "swarm_forage/core/util/simd.hpp"

namespace swarm_forage {
namespace {

bool avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") != 0;
}

uint64_t bitsOf(double v) {
  uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

/// Restores the switch the process started with, whatever a test set.
class SimdSwitch : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!avx2()) GTEST_SKIP() << "no AVX2 on this CPU";
    was_ = simdEnabled();
  }
  void TearDown() override { setSimdEnabled(was_); }
  bool was_ = false;
};

SWARM_FORAGE_AVX2 void sinCos4(const double* a, double* s, double* c) {
  __m256d vs, vc;
  fastSinCos4(_mm256_loadu_pd(a), vs, vc);
  _mm256_storeu_pd(s, vs);
  _mm256_storeu_pd(c, vc);
}

SWARM_FORAGE_AVX2 void atan2_4(const double* y, const double* x, double* a) {
  __m256d out;
  fastAtan2_4(_mm256_loadu_pd(y), _mm256_loadu_pd(x), out);
  _mm256_storeu_pd(a, out);
}

std::vector<double> angles() {
  std::vector<double> v = {0.0,  -0.0,  1e-300, -1e-300, 5e-324, -5e-324, 1e6,   -1e6,
                           1e15, -1e15, 4e15,   -4e15,   1e18,   -1e18,   1e300, -1e300};
  for (int k = -64; k <= 64; ++k)  // quadrant boundaries (pi/4 apart) and the doubles either side
    for (const double a : {k * 0.78539816339744830962, k * 1.57079632679489661923}) {
      v.push_back(a);
      v.push_back(std::nextafter(a, 1e300));
      v.push_back(std::nextafter(a, -1e300));
    }
  std::mt19937_64 gen(25);
  for (const double range : {1.0, 4.0, 10.0, 1e3, 1e6, 1e12})
    for (int k = 0; k < 65536; ++k) v.push_back(std::uniform_real_distribution<double>(-range, range)(gen));
  while (v.size() % 4) v.push_back(0.5);
  return v;
}

TEST_F(SimdSwitch, SinCosHasTheScalarBits) {
  const std::vector<double> a = angles();
  for (std::size_t k = 0; k < a.size(); k += 4) {
    double s[4], c[4];
    sinCos4(&a[k], s, c);
    for (std::size_t j = 0; j < 4; ++j) {
      double ss, cc;
      fastSinCos(a[k + j], ss, cc);
      ASSERT_EQ(bitsOf(s[j]), bitsOf(ss)) << "sin " << a[k + j];
      ASSERT_EQ(bitsOf(c[j]), bitsOf(cc)) << "cos " << a[k + j];
    }
  }
}

TEST_F(SimdSwitch, Atan2HasTheScalarBits) {
  std::vector<double> y, x;
  const double edges[] = {0.0,     -0.0,   1.0,   -1.0,   0.66, -0.66, 1e-300,
                          -1e-300, 5e-324, 1e300, -1e300, 3.0,  -2.0};
  for (const double a : edges)
    for (const double b : edges) {
      y.push_back(a);
      x.push_back(b);
    }
  std::mt19937_64 gen(26);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < (1 << 18); ++k) {
    const double scale = std::pow(10.0, static_cast<int>(gen() % 21) - 10);  // 1e-10 .. 1e10
    double a = u(gen) * scale, b = u(gen) * scale;
    switch (gen() % 6) {  // the branch points: the diagonal, the 0.66 ratio, the axes
      case 0:
        a = std::copysign(b, a);
        break;
      case 1:
        a = std::nextafter(0.66 * std::fabs(b), gen() % 2 ? 1e300 : 0.0);
        break;
      case 2:
        b = gen() % 2 ? 0.0 : -0.0;
        break;
      default:
        break;
    }
    y.push_back(a);
    x.push_back(b);
  }
  while (y.size() % 4) {
    y.push_back(1);
    x.push_back(1);
  }
  for (std::size_t k = 0; k < y.size(); k += 4) {
    double a[4];
    atan2_4(&y[k], &x[k], a);
    for (std::size_t j = 0; j < 4; ++j)
      ASSERT_EQ(bitsOf(a[j]), bitsOf(fastAtan2(y[k + j], x[k + j]))) << y[k + j] << " " << x[k + j];
  }
}

TEST_F(SimdSwitch, WanderMotionForcesAndSteeringHaveTheScalarBits) {
  const CrwConfig c;
  std::mt19937_64 gen(27);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::size_t n = 4099;
  std::vector<float> angle0(n);
  std::vector<double> step(n);
  std::vector<Vec2> force(n);
  std::vector<uint8_t> mode(n);
  std::vector<uint32_t> robots;
  for (std::size_t l = 0; l < n; ++l) {
    angle0[l] = static_cast<float>(u(gen) * c.wander_limit);
    step[l] = u(gen) * c.wander_step;
    force[l] = Vec2(u(gen), u(gen)) * (gen() % 8 == 0 ? 1e-8 : 12.0);  // some below steer's 1e-9 m/s
    if (gen() % 9 == 0) force[l].x() = 0.0;
    if (gen() % 9 == 0) force[l].y() = -0.0;
    mode[l] = static_cast<uint8_t>(gen() % 3);
    if (gen() % 3) robots.push_back(static_cast<uint32_t>(l));
  }
  SensorData sd;  // motion forces: every motion, threatened or not, slow or not, with and without light
  sd.resize(n);
  std::vector<uint8_t> motion(n), slow(n);
  for (std::size_t l = 0; l < n; ++l) {
    sd.threatened[l] = gen() % 2;
    sd.obstacle_x[l] = gen() % 7 ? static_cast<float>(u(gen)) : 0.f;
    sd.obstacle_y[l] = gen() % 7 ? static_cast<float>(u(gen)) : -0.f;
    sd.light_x[l] = gen() % 7 ? static_cast<float>(u(gen)) : 0.f;
    sd.light_y[l] = gen() % 7 ? static_cast<float>(u(gen)) : 0.f;
    motion[l] = gen() % 5 == 4 ? 0xff : static_cast<uint8_t>(gen() % 4);
    slow[l] = gen() % 2;
  }
  std::vector<Vec2> moved[2] = {force, force};
  std::vector<uint8_t> moved_soft[2] = {mode, mode};
  for (int simd = 0; simd < 2; ++simd) {
    setSimdEnabled(simd != 0);
    motionForces(motion.data(), slow.data(), sd, 0, static_cast<uint32_t>(n), c, moved[simd].data(),
                 moved_soft[simd].data());
  }
  EXPECT_EQ(std::memcmp(moved[0].data(), moved[1].data(), n * sizeof(Vec2)), 0);
  EXPECT_EQ(moved_soft[0], moved_soft[1]);
  std::vector<float> angle[2] = {angle0, angle0};
  std::vector<Vec2> wander[2] = {force, force};
  std::vector<WheelSpeeds> wheels[2] = {std::vector<WheelSpeeds>(n), std::vector<WheelSpeeds>(n)};
  for (int simd = 0; simd < 2; ++simd) {
    setSimdEnabled(simd != 0);
    wanderForces(robots.data(), robots.size(), angle[simd].data(), step.data(), wander[simd].data(), c);
    steerAll(force.data(), mode.data(), wheels[simd].data(), n, c.drive);
  }
  EXPECT_EQ(std::memcmp(angle[0].data(), angle[1].data(), n * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(wander[0].data(), wander[1].data(), n * sizeof(Vec2)), 0);
  EXPECT_EQ(std::memcmp(wheels[0].data(), wheels[1].data(), n * sizeof(WheelSpeeds)), 0);
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Each controller's commands, status and the bodies they move, tick by tick, with the 4-lane paths on and
// off; also with FORDYCA 2019's quirks (its velocity and heading estimates read the finished state).
TEST_F(SimdSwitch, RunsHaveTheSameBitsWithAndWithoutSimd) {
  for (const std::string quirks : {"", "fordyca_2019"})
    for (const std::string kind : {"crw", "dpo", "gp_dpo"}) {
      WorldConfig c;
      if (!quirks.empty()) c.quirks = FordycaQuirks::parse(quirks, "");
      c.arena.name = "32x16";
      c.arena.width = 32;
      c.arena.height = 16;
      c.arena.n_blocks = 100;
      c.n_robots = 1023;  // not a multiple of 4: the scalar tails run too
      c.seed = 7;
      Simulation on(c, kind), off(c, kind);
      for (int t = 0; t < 300; ++t) {
        const double throttle = t < 150 ? 0.0 : 0.5;
        setSimdEnabled(true);
        on.step(throttle);
        setSimdEnabled(false);
        off.step(throttle);
        ASSERT_TRUE(sameBits(on.commands().left, off.commands().left))
            << kind << " " << quirks << " tick " << t;
        ASSERT_TRUE(sameBits(on.commands().right, off.commands().right))
            << kind << " " << quirks << " tick " << t;
        ASSERT_TRUE(sameBits(on.commands().request, off.commands().request))
            << kind << " " << quirks << " tick " << t;
        const ControllerStatus &sa = on.status(), &sb = off.status();
        ASSERT_TRUE(sa.stalled == sb.stalled && sa.in_avoidance == sb.in_avoidance &&
                    sa.state_counts == sb.state_counts)
            << kind << " " << quirks << " tick " << t;
        const RobotBodies &a = on.world().robots(), &b = off.world().robots();
        ASSERT_TRUE(sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.theta, b.theta))
            << kind << " " << quirks << " tick " << t;
      }
    }
}

}  // namespace
}  // namespace swarm_forage
