#pragma once
// A Levy-walk forager written only against swarm_forage's public headers (docs/your-own-controller.md):
// explore by straight steps of truncated power-law length in uniformly random directions, take the first
// block found to the nest by phototaxis, drop it there and leave, as CRW does.
#include <cstdint>
#include <string>

#include "swarm_forage/core/controllers/controller_constants.hpp"
#include "swarm_forage/core/controllers/forager_batch.hpp"  // ForagerBatch, CrwConfig, the motion helpers

namespace swarm_forage_examples {

/// The kind's name: the ~controller value and the YAML section of config/levy.yaml.
constexpr const char* kLevyKind = "swarm_forage_examples/levy";

/// The Levy walker's own constants (config/levy.yaml holds the same defaults).
struct LevyConfig {
  // p(l) ~ l^-mu on [l_min, l_max]. mu = 2 is the optimum for sparse, revisitable targets (Viswanathan
  // et al., Nature 401, 1999): blocks here reappear in the source. mu -> 1 is ballistic, mu >= 3 Brownian.
  double mu = 2.0;
  double l_min = 0.2;       // [m] the detection scale: a robot finds a block by standing on it (0.2 m blocks)
  double l_max = 32.0;      // [m] the longest straight path in a 32 x 16 arena; longer steps end at a wall
  double step_force = 6.3;  // [cm/s] speed along a step: CRW's free exploring speed (9 x 0.7)
  double avoidance_force = 8.0;  // [cm/s] away from a threatening obstacle (CRW's)

  void validate() const;  // throws swarm_forage::ParameterError naming the key and its range
};

/// The Levy walker's constants under their YAML names.
void visitLevyParameters(LevyConfig& c, swarm_forage::ConstantVisitor& v);

/// Inverse-CDF draw from p(l) ~ l^-mu on [l_min, l_max] for u uniform in [0, 1).
double levyStepLength(double u, double mu, double l_min, double l_max);

enum class LevyState : uint8_t { kExplore, kPickup, kTransport, kNestWander, kDrop, kLeaveNest, kCount };

class LevyBatch : public swarm_forage::ForagerBatch {
 public:
  /// Exploration from `levy`; carrying, the nest and leaving it from `crw` (the kind builds on CRW).
  LevyBatch(const LevyConfig& levy, const swarm_forage::CrwConfig& crw, uint32_t seed, uint32_t first_id,
            uint32_t count);
  std::string name() const override { return kLevyKind; }
  void step(uint64_t tick, const swarm_forage::SensorData& sensors, swarm_forage::CommandData& commands,
            swarm_forage::ControllerStatus& status) override;

  LevyState state(uint32_t local) const { return static_cast<LevyState>(state_[local]); }
  /// Every step robot `local` has started: its length [m] (tests read the distribution).
  uint64_t stepsStarted(uint32_t local) const { return steps_started_[local]; }
  double lastStepLength(uint32_t local) const { return step_length_[local]; }

 protected:
  /// A newcomer (population dynamics): ForagerBatch's state and its step forgotten.
  void restart(uint32_t local) override;

 private:
  swarm_forage::WheelSpeeds explore(uint32_t local, uint64_t tick, const swarm_forage::SensorData& s);

  LevyConfig levy_;
  swarm_forage::CrwConfig crw_;
  // The current step of each robot: its world heading, length and what is left of it [m]; remaining <= 0
  // means a new step starts at the next exploring tick without a threat.
  std::vector<double> heading_, step_length_, remaining_;
  std::vector<float> last_x_, last_y_;
  std::vector<uint64_t> steps_started_;
};

}  // namespace swarm_forage_examples
