#include "swarm_forage/core/world/saa_noise.hpp"

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/util/geometry.hpp"
#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

namespace {
constexpr uint64_t kGroundKey = 5;  // the ground sensor's draws, after the five devices with a model
constexpr uint64_t kKeys = 8;       // RNG ids per robot: id * kKeys + device

CounterRng deviceRng(uint32_t seed, uint64_t id, uint64_t device, uint64_t tick) {
  return CounterRng(seed, RngStream::kNoise, id * kKeys + device, tick);
}

double draw(const DeviceNoise& d, CounterRng& rng) {
  return d.model == NoiseModel::kGaussian ? d.level * rng.gaussian() : rng.uniform(-d.level, d.level);
}
}  // namespace

std::string DeviceNoise::word() const {
  return std::string(model == NoiseModel::kGaussian ? "gaussian:" : "uniform:") + canonicalNumber(level);
}

const std::vector<std::string>& SaaNoise::deviceNames() {
  static const std::vector<std::string> names{"proximity", "light", "position", "heading", "wheels"};
  return names;
}

DeviceNoise& SaaNoise::device(NoisyDevice d) {
  return const_cast<DeviceNoise&>(static_cast<const SaaNoise&>(*this).device(d));
}

const DeviceNoise& SaaNoise::device(NoisyDevice d) const {
  switch (d) {
    case NoisyDevice::kProximity:
      return proximity;
    case NoisyDevice::kLight:
      return light;
    case NoisyDevice::kPosition:
      return position;
    case NoisyDevice::kHeading:
      return heading;
    case NoisyDevice::kWheels:
      break;
  }
  return wheels;
}

double SaaNoise::maxLevel(NoisyDevice d) {
  // Bounds that keep a reading meaningful: a body's length scale for the vectors, half a turn for the
  // heading, and a gain noise that can at most stop or double a wheel.
  switch (d) {
    case NoisyDevice::kProximity:
    case NoisyDevice::kLight:
    case NoisyDevice::kPosition:
      return 10.0;
    case NoisyDevice::kHeading:
      return kPi;
    case NoisyDevice::kWheels:
      break;
  }
  return 1.0;
}

void SaaNoise::validate() const {
  for (std::size_t k = 0; k < deviceNames().size(); ++k) {
    const auto d = static_cast<NoisyDevice>(k);
    const double v = device(d).level, hi = maxLevel(d);
    if (!(v >= 0 && v <= hi))
      throw ParameterError("noise/" + deviceNames()[k] + "/level must be a number in [0, " +
                           canonicalNumber(hi) + "] (" +
                           (device(d).model == NoiseModel::kGaussian ? "sigma" : "half-width") + "; got " +
                           canonicalNumber(v) + ")");
  }
  if (!(ground >= 0 && ground <= 1))
    throw ParameterError("noise/ground/level must be a probability in [0, 1] (got " +
                         canonicalNumber(ground) + ")");
}

std::string SaaNoise::describe() const {
  std::string s;
  const auto add = [&s](const std::string& name, const std::string& value) {
    s += (s.empty() ? "" : " ") + ("noise/" + name) + "=" + value;
  };
  if (proximity.on()) add("proximity", proximity.word());
  if (light.on()) add("light", light.word());
  if (ground > 0) add("ground", canonicalNumber(ground));
  if (position.on()) add("position", position.word());
  if (heading.on()) add("heading", heading.word());
  if (wheels.on()) add("wheels", wheels.word());
  return s;
}

std::string SaaNoise::tag() const {
  if (!enabled()) return "";
  const auto named = [](const DeviceNoise& d) {
    return std::string(d.model == NoiseModel::kGaussian ? "gaussian" : "uniform") + canonicalNumber(d.level);
  };
  bool same = ground == proximity.level;
  for (std::size_t k = 0; k < deviceNames().size(); ++k) {
    const DeviceNoise& d = device(static_cast<NoisyDevice>(k));
    same = same && d.model == proximity.model && d.level == proximity.level;
  }
  if (same) return "saa-all-" + named(proximity);
  std::string s = "saa";
  for (std::size_t k = 0; k < deviceNames().size(); ++k) {
    const DeviceNoise& d = device(static_cast<NoisyDevice>(k));
    if (d.on()) s += "-" + deviceNames()[k] + "-" + named(d);
  }
  if (ground > 0) s += "-ground" + canonicalNumber(ground);
  return s;
}

void SaaNoise::perturbReadings(SensorData& s, std::size_t first, std::size_t end, uint32_t seed,
                               uint64_t tick, int ground_kinds) const {
  const auto pair = [&](const DeviceNoise& d, NoisyDevice key, std::size_t i, float& a, float& b) {
    CounterRng rng = deviceRng(seed, i, static_cast<uint64_t>(key), tick);
    a = static_cast<float>(a + draw(d, rng));
    b = static_cast<float>(b + draw(d, rng));
  };
  for (std::size_t i = first; i < end; ++i) {
    // A proximity sensor that sees nothing reads nothing: the noise perturbs a reading, it invents none.
    if (proximity.on() && s.threatened[i])
      pair(proximity, NoisyDevice::kProximity, i, s.obstacle_x[i], s.obstacle_y[i]);
    if (light.on()) pair(light, NoisyDevice::kLight, i, s.light_x[i], s.light_y[i]);
    if (position.on()) pair(position, NoisyDevice::kPosition, i, s.x[i], s.y[i]);
    if (heading.on()) {
      CounterRng rng = deviceRng(seed, i, static_cast<uint64_t>(NoisyDevice::kHeading), tick);
      s.theta[i] = static_cast<float>(wrapAngle(s.theta[i] + draw(heading, rng)));
    }
    if (ground > 0 && ground_kinds > 1) {
      CounterRng rng = deviceRng(seed, i, kGroundKey, tick);
      if (rng.uniform() < ground) {
        const int other = static_cast<int>(rng.uniform() * (ground_kinds - 1));  // one of the other kinds
        s.ground[i] = static_cast<uint8_t>(other < s.ground[i] ? other : other + 1);
      }
    }
  }
}

void SaaNoise::perturbWheels(float& left, float& right, uint32_t id, uint32_t seed, uint64_t tick,
                             double max_speed) const {
  CounterRng rng = deviceRng(seed, id, static_cast<uint64_t>(NoisyDevice::kWheels), tick);
  // The motors cannot exceed their top speed: held after the gain, which also keeps the world's bound on
  // how far a robot moves in a tick (world_motion.cpp).
  const double l = std::clamp<double>(left, -max_speed, max_speed) * (1.0 + draw(wheels, rng));
  const double r = std::clamp<double>(right, -max_speed, max_speed) * (1.0 + draw(wheels, rng));
  left = static_cast<float>(std::clamp(l, -max_speed, max_speed));
  right = static_cast<float>(std::clamp(r, -max_speed, max_speed));
}

}  // namespace swarm_forage
