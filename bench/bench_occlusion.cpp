// The light_occlusion quirk measured (docs/FIDELITY.md, "FORDYCA as it ran", (8)): how often robots shadow
// the nest lights in a crowd, and what the occlusion costs per tick. Prints; asserts nothing.
//
//   bench_occlusion
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "swarm_forage/core/run/simulation.hpp"

namespace swarm_forage {
namespace {

// How often robots shadow the nest lights in a crowd (seed 1).
void measureShadowing() {
  struct Case {
    const char* kind;
    double w, h;
    uint32_t blocks, n, ticks;
  };
  for (const Case k : {Case{"dpo", 64, 32, 200, 1024, 20000}, Case{"crw", 96, 48, 450, 8192, 5000}}) {
    WorldConfig c;
    c.arena.name = std::to_string(static_cast<int>(k.w)) + "x" + std::to_string(static_cast<int>(k.h));
    c.arena.width = k.w;
    c.arena.height = k.h;
    c.arena.n_blocks = k.blocks;
    c.n_robots = k.n;
    c.seed = 1;
    c.quirks.set(Quirk::kLightOcclusion);
    Simulation sim(c, k.kind, ControllerConfigs{}, 1);
    uint64_t shadowed = 0, carrier_ticks = 0, carrier_shadowed = 0, blind = 0;
    for (uint32_t t = 1; t <= k.ticks; ++t) {
      sim.step();
      shadowed += sim.world().shadowedLights();
      const SensorData& r = sim.sensors();
      for (uint32_t i = 0; i < k.n; ++i) {
        if (r.carried_block[i] < 0) continue;
        ++carrier_ticks;
        const uint8_t m = sim.world().shadowMasks()[i];
        carrier_shadowed += m != 0;
        blind += m == 7;
      }
      if (t % (k.ticks / 5) == 0) {
        std::printf(
            "%s %s N=%u tick %u: P=%llu, shadowed (robot, light) pairs this tick %llu of %u; "
            "carriers with a light shadowed %.4f (all shadowed %.5f) since the start\n",
            k.kind, c.arena.name.c_str(), k.n, t, static_cast<unsigned long long>(sim.world().delivered()),
            static_cast<unsigned long long>(sim.world().shadowedLights()), 3 * k.n,
            carrier_ticks ? static_cast<double>(carrier_shadowed) / carrier_ticks : 0.0,
            carrier_ticks ? static_cast<double>(blind) / carrier_ticks : 0.0);
      }
    }
    std::printf("%s: mean shadowed pairs per tick %.2f (of %u)\n", k.kind,
                static_cast<double>(shadowed) / k.ticks, 3 * k.n);
  }
}

// The cost of light_occlusion per tick, CRW 96x48, N = 8,192, off and on twice in one run.
void measureCost() {
  for (const bool on : {false, true, false, true}) {
    WorldConfig c;
    c.arena.name = "96x48";
    c.arena.width = 96;
    c.arena.height = 48;
    c.arena.n_blocks = 450;
    c.n_robots = 8192;
    c.seed = 1;
    c.quirks.set(Quirk::kLightOcclusion, on);
    Simulation sim(c, "crw", ControllerConfigs{}, 1);
    for (int t = 0; t < 3000; ++t) sim.step();  // carriers spread between the source and the nest
    const auto start = std::chrono::steady_clock::now();
    for (int t = 0; t < 300; ++t) sim.step();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("light_occlusion %s: %.2f ms per tick (1 thread)\n", on ? "on " : "off", ms / 300);
  }
}

}  // namespace
}  // namespace swarm_forage

int main() {
  swarm_forage::measureShadowing();
  swarm_forage::measureCost();
  return 0;
}
