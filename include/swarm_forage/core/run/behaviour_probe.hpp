#pragma once
// Measurements of how robots move and forage, for the behaviour tests and bench_behaviour: a lone
// robot's path in open space (speed, net displacement, persistence length) and a lone robot's
// deliveries in an arena. Headless and deterministic for one seed.
#include <cstdint>
#include <string>

#include "swarm_forage/core/controllers/controller_registry.hpp"

namespace swarm_forage {

struct PathStats {
  double path = 0;        // m travelled, summed tick by tick
  double net = 0;         // m between the first and the last position
  double mean_speed = 0;  // m/s over the ticks
};

/// One CRW robot exploring alone, from the centre of a 220 x 150 m arena: for `ticks` <= 1,000 (63 m) no
/// wall, nest or block is within reach, so the path is the random walk alone.
PathStats loneExplorerPath(const ControllerConfigs& configs, uint32_t seed, uint64_t ticks);

/// The persistence length L_p [m] of a worm-like path whose mean squared end-to-end distance over
/// path length L is msd: msd = 2 L_p L - 2 L_p^2 (1 - exp(-L / L_p)). Straighter paths give larger L_p.
double persistenceLength(double msd, double length);

/// Blocks a single robot of `controller` delivers in `arena` in `ticks` ticks.
uint64_t loneDeliveries(const std::string& controller, const ArenaConfig& arena, uint32_t seed,
                        uint64_t ticks, const ControllerConfigs& configs = {});

}  // namespace swarm_forage
