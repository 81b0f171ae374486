// ~noise/<device>/model and ~noise/<device>/level (docs/robustness.md, Sensor and actuator noise).
#include <algorithm>

#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

namespace {
const std::vector<std::string> kModels{"gaussian", "uniform"};

NoiseModel modelNamed(const std::string& name) {
  return name == "uniform" ? NoiseModel::kUniform : NoiseModel::kGaussian;
}
}  // namespace

std::vector<std::string> noiseParams() {
  std::vector<std::string> names{"noise/all/model", "noise/all/level", "noise/ground/level"};
  for (const std::string& d : SaaNoise::deviceNames()) {
    names.push_back("noise/" + d + "/model");
    names.push_back("noise/" + d + "/level");
  }
  return names;
}

SaaNoise readNoise(const ParamSource& p) {
  // noise/all sets every device at once (ground: its level is the misread probability); a device's own
  // keys override it.
  const std::string all_model = paramOneOf(p, "noise/all/model", "gaussian", kModels);
  const double all_level = paramInRange(p, "noise/all/level", 0.0, 0.0, 1.0);
  SaaNoise noise;
  for (std::size_t k = 0; k < SaaNoise::deviceNames().size(); ++k) {
    const auto d = static_cast<NoisyDevice>(k);
    const std::string prefix = "noise/" + SaaNoise::deviceNames()[k] + "/";
    noise.device(d).model = modelNamed(paramOneOf(p, prefix + "model", all_model, kModels));
    noise.device(d).level = paramInRange(p, prefix + "level", all_level, 0.0, SaaNoise::maxLevel(d));
  }
  noise.ground = paramInRange(p, "noise/ground/level", all_level, 0.0, 1.0);
  noise.validate();
  return noise;
}

}  // namespace swarm_forage
