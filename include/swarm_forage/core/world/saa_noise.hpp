#pragma once
// Sensor and actuator ("SAA") noise (docs/robustness.md, Sensor and actuator noise): what each robot
// perceives and what its wheels do, perturbed per device. Every draw comes from the counter-based RNG
// keyed by (seed, robot, device, tick), so a run is bit-identical for any thread count or controller
// split, and turning one device on does not change another's draws.
#include <cstdint>
#include <string>
#include <vector>

#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

enum class NoiseModel : uint8_t { kGaussian, kUniform };

/// One device's additive noise: gaussian with sigma = level, or uniform on [-level, level].
struct DeviceNoise {
  NoiseModel model = NoiseModel::kGaussian;
  double level = 0;
  bool on() const { return level > 0; }
  /// "gaussian:0.01" / "uniform:0.01".
  std::string word() const;
};

/// The devices that take a model, in the order of their words and draws.
enum class NoisyDevice : uint8_t { kProximity, kLight, kPosition, kHeading, kWheels };

struct SaaNoise {
  DeviceNoise proximity;  // the obstacle vector [m], each component, when a threat is seen
  DeviceNoise light;      // the light vector, each component
  DeviceNoise position;   // the position the robot believes [m], each coordinate
  DeviceNoise heading;    // the heading the robot believes [rad]
  DeviceNoise wheels;     // each wheel's speed x (1 + noise), then held to +-max_speed
  double ground = 0;      // probability that the ground sensor reads another ground kind

  /// Device names as parameters and words use them (noise/<name>/...): the five with a model.
  static const std::vector<std::string>& deviceNames();
  DeviceNoise& device(NoisyDevice d);
  const DeviceNoise& device(NoisyDevice d) const;
  /// The largest level each device accepts (ground: a probability, 1).
  static double maxLevel(NoisyDevice d);

  bool sensorsOn() const {
    return proximity.on() || light.on() || position.on() || heading.on() || ground > 0;
  }
  bool enabled() const { return sensorsOn() || wheels.on(); }
  /// Throws ParameterError naming noise/<device>/level and its valid range.
  void validate() const;
  /// Identity words of the devices with noise ("noise/light=uniform:0.02 noise/ground=0.05"); empty when off.
  std::string describe() const;
  /// A short name for record names: "saa-all-gaussian0.03" when every device has one noise, else the devices
  /// with noise ("saa-light-uniform0.02-ground0.05"); empty when off.
  std::string tag() const;

  /// Perturbs robots [first, end) of `s` (perceived readings, filled from the truth) for `tick`.
  /// `ground_kinds`: how many ground kinds the arena has (a misread is one of the others, uniformly).
  void perturbReadings(SensorData& s, std::size_t first, std::size_t end, uint32_t seed, uint64_t tick,
                       int ground_kinds) const;
  /// Wheel speeds of robot `id` at `tick` after the wheel noise, each held to [-max_speed, max_speed].
  void perturbWheels(float& left, float& right, uint32_t id, uint32_t seed, uint64_t tick,
                     double max_speed) const;
};

}  // namespace swarm_forage
