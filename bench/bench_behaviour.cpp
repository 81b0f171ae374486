// How robots move and forage alone (docs/FIDELITY.md): a lone CRW robot's path in open space over 30
// seeds (speed, rms net displacement, persistence length), and the blocks a lone robot of each kind
// delivers in 32x16 and 64x32 over T = 10,000 s (10 seeds).
//
//   bench_behaviour [--ticks-open 1000] [--ticks-arena 50000]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "swarm_forage/core/run/behaviour_probe.hpp"

int main(int argc, char** argv) {
  uint64_t open_ticks = 1000, arena_ticks = 50000;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string opt = argv[i];
    const uint64_t v = std::strtoull(argv[i + 1], nullptr, 10);
    if (opt == "--ticks-open")
      open_ticks = v;
    else if (opt == "--ticks-arena")
      arena_ticks = v;
  }
  using namespace swarm_forage;
  const int seeds = 30;
  double path = 0, msd = 0, speed = 0;
  for (int s = 1; s <= seeds; ++s) {
    const PathStats p = loneExplorerPath({}, static_cast<uint32_t>(s), open_ticks);
    path += p.path / seeds;
    msd += p.net * p.net / seeds;
    speed += p.mean_speed / seeds;
  }
  std::printf(
      "lone CRW explorer, open 220x150 m, %llu ticks, %d seeds: speed %.2f cm/s, path %.2f m, "
      "rms net displacement %.2f m, persistence length %.2f m\n",
      static_cast<unsigned long long>(open_ticks), seeds, 100 * speed, path, std::sqrt(msd),
      persistenceLength(msd, path));
  for (const auto& [name, w, h, blocks] :
       {std::tuple<const char*, double, double, uint32_t>{"32x16", 32, 16, 50}, {"64x32", 64, 32, 200}}) {
    ArenaConfig a;
    a.name = name;
    a.width = w;
    a.height = h;
    a.n_blocks = blocks;
    for (const char* kind : {"crw", "dpo", "gp_dpo"}) {
      std::string counts;
      double mean = 0;
      for (uint32_t s = 1; s <= 10; ++s) {
        const uint64_t d = loneDeliveries(kind, a, s, arena_ticks);
        counts += (counts.empty() ? "" : " ") + std::to_string(d);
        mean += d / 10.0;
      }
      std::printf("lone %s robot in %s, %llu ticks, seeds 1-10: %.1f blocks on average (%s)\n", kind, name,
                  static_cast<unsigned long long>(arena_ticks), mean, counts.c_str());
      std::fflush(stdout);
    }
  }
  return 0;
}
