#include "swarm_forage/core/run/behaviour_probe.hpp"

#include <cmath>
#include <stdexcept>

#include "swarm_forage/core/run/simulation.hpp"

namespace swarm_forage {

PathStats loneExplorerPath(const ControllerConfigs& configs, uint32_t seed, uint64_t ticks) {
  if (ticks > 1000) throw std::invalid_argument("loneExplorerPath: at most 1,000 ticks stay in open space");
  WorldConfig c;  // from the centre, 66 m to the source, 77 m to the nest, 75 m to a wall: out of reach
  c.arena.name = "open220x150";
  c.arena.width = 220;
  c.arena.height = 150;
  c.n_robots = 1;
  c.seed = seed;
  Simulation sim(c, "crw", configs);
  const RobotBodies& body = sim.world().robots();
  sim.world().setPose(0, 110, 75, body.theta[0]);
  PathStats p;
  double x = body.x[0], y = body.y[0];
  const double x0 = x, y0 = y;
  for (uint64_t k = 0; k < ticks; ++k) {
    sim.step();
    p.path += std::hypot(body.x[0] - x, body.y[0] - y);
    x = body.x[0];
    y = body.y[0];
  }
  p.net = std::hypot(x - x0, y - y0);
  p.mean_speed = ticks > 0 ? p.path / (static_cast<double>(ticks) * sim.world().config().dt()) : 0.0;
  return p;
}

double persistenceLength(double msd, double length) {
  if (!(length > 0) || !(msd > 0)) return 0.0;
  if (msd >= length * length) return INFINITY;  // a straight line
  const auto model = [length](double lp) {
    return 2 * lp * length - 2 * lp * lp * (1 - std::exp(-length / lp));
  };
  double lo = 1e-9, hi = 1e9;  // the model grows with lp, from 0 to length^2
  for (int k = 0; k < 200; ++k) {
    const double mid = std::sqrt(lo * hi);
    (model(mid) < msd ? lo : hi) = mid;
  }
  return std::sqrt(lo * hi);
}

uint64_t loneDeliveries(const std::string& controller, const ArenaConfig& arena, uint32_t seed,
                        uint64_t ticks, const ControllerConfigs& configs) {
  WorldConfig c;
  c.arena = arena;
  c.n_robots = 1;
  c.seed = seed;
  Simulation sim(c, controller, configs);
  for (uint64_t k = 0; k < ticks; ++k) sim.step();
  return sim.world().delivered();
}

}  // namespace swarm_forage
