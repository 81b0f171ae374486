#pragma once
// What bench_fidelity's modes share: the arenas by name and the stall count of --trace.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "swarm_forage/core/run/simulation.hpp"

namespace swarm_forage::fidelity {

inline ArenaConfig arenaNamed(const std::string& name) {
  ArenaConfig a;
  a.name = name;
  if (name == "64x32") {
    a.width = 64, a.height = 32, a.n_blocks = 200;
  } else if (name == "96x48") {
    a.width = 96, a.height = 48, a.n_blocks = 460;
  } else if (name != "32x16") {
    std::fprintf(stderr, "bench_fidelity: --arena must be 32x16, 64x32 or 96x48\n");
    std::exit(2);
  }
  return a;
}

struct Stalls {  // robots that have not moved 1 cm within the last 50 ticks
  std::vector<double> ax, ay;
  std::vector<uint64_t> since;
  uint32_t count(const RobotBodies& b, uint64_t tick) {
    if (ax.empty()) ax = b.x, ay = b.y, since.assign(b.size(), tick);
    uint32_t n = 0;
    for (std::size_t i = 0; i < b.size(); ++i) {
      if (std::hypot(b.x[i] - ax[i], b.y[i] - ay[i]) > 0.01) ax[i] = b.x[i], ay[i] = b.y[i], since[i] = tick;
      n += tick - since[i] >= 50;
    }
    return n;
  }
};

}  // namespace swarm_forage::fidelity
