// The numpy CRW (a Python controller in process, examples/swarm_forage_examples) against the C++ CRW,
// headless (World + one batch, as bench_core): robot-ticks/s of each and their ratio at N = 64 and 1,024 in
// 32x16 and 16,384 in 96x48, and the embedded interpreter's own cost per tick (a class whose step does
// nothing).
//
//   bench_python                 # every case, 300 ticks each (after 20 to warm up)
//   bench_python --ticks 1000 --threads 1
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/core/world/world.hpp"
#include "swarm_forage/python/python_controllers.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace swarm_forage;

struct Timing {
  double total = 0, control = 0;  // seconds over the measured ticks
};

ArenaConfig arena(double width, double height, uint32_t blocks) {
  ArenaConfig a;
  a.name = std::to_string(static_cast<int>(width)) + "x" + std::to_string(static_cast<int>(height));
  a.width = width;
  a.height = height;
  a.n_blocks = blocks;
  return a;
}

Timing run(const std::string& controller, const ArenaConfig& a, uint32_t n, uint64_t ticks,
           unsigned threads) {
  WorldConfig wc;
  wc.arena = a;
  wc.n_robots = n;
  wc.seed = 1;
  World world(configuredFor(wc, controller));
  const auto pool = std::make_shared<WorkerPool>(threads);
  world.setPool(pool);
  const Rect nest = a.nest();
  const auto configs =
      sharingWorld({}, {(nest.min_x + nest.max_x) / 2, (nest.min_y + nest.max_y) / 2}, world.config().sight);
  const auto batch = makeController(controller, configs, 1, 0, n, pool);
  SensorData sensors;
  CommandData commands;
  ControllerStatus status;
  sensors.resize(n);
  commands.resize(n);
  Timing t;
  for (uint64_t k = 0; k < ticks + 20; ++k) {
    const auto a0 = Clock::now();
    world.sense(sensors);
    const auto b = Clock::now();
    batch->step(world.tick(), sensors, commands, status);
    const auto c = Clock::now();
    world.step(commands, 0.0);
    if (k < 20) continue;  // warm-up: numpy's first calls, caches
    t.total += std::chrono::duration<double>(Clock::now() - a0).count();
    t.control += std::chrono::duration<double>(c - b).count();
  }
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  uint64_t ticks = 300;
  unsigned threads = 0;
  for (int k = 1; k + 1 < argc; k += 2) {
    const std::string flag = argv[k];
    if (flag == "--ticks")
      ticks = std::strtoull(argv[k + 1], nullptr, 10);
    else if (flag == "--threads")
      threads = static_cast<unsigned>(std::strtoul(argv[k + 1], nullptr, 10));
    else {
      std::fprintf(stderr, "usage: %s [--ticks K (default 300)] [--threads T (default 0: one per core)]\n",
                   argv[0]);
      return 2;
    }
  }
  if (ticks == 0) {
    std::fprintf(stderr, "%s: --ticks must be at least 1\n", argv[0]);
    return 2;
  }
  const std::string source = SWARM_FORAGE_SOURCE_DIR;
  setenv("PYTHONPATH", (source + "/bench").c_str(), 1);  // read when the interpreter starts
  try {
    registerKind(pythonKind({"swarm_forage_examples/numpy_crw", "swarm_forage_examples.numpy_crw.NumpyCrw",
                             source + "/examples/swarm_forage_examples", "bench_python"}));
    registerKind(pythonKind({"bench/idle", "bench_python_idle.Idle", source + "/bench", "bench_python"}));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_python: %s\n", e.what());
    return 1;
  }
  struct Case {
    uint32_t n;
    ArenaConfig a;
  };
  const Case cases[] = {{64, arena(32, 16, 50)}, {1024, arena(32, 16, 50)}, {16384, arena(96, 48, 460)}};
  std::printf("%-8s %-6s %16s %16s %7s %14s %14s %14s\n", "N", "arena", "C++ CRW r-t/s", "numpy CRW r-t/s",
              "ratio", "CRW ctl us/t", "numpy ctl us/t", "idle ctl us/t");
  for (const Case& c : cases) {
    const Timing crw = run("crw", c.a, c.n, ticks, threads);
    const Timing py = run("swarm_forage_examples/numpy_crw", c.a, c.n, ticks, threads);
    const Timing idle = run("bench/idle", c.a, c.n, ticks, threads);
    const double robot_ticks = static_cast<double>(c.n) * static_cast<double>(ticks);
    const double per_tick = 1e6 / static_cast<double>(ticks);
    std::printf("%-8u %-6s %16.3e %16.3e %7.2f %14.1f %14.1f %14.1f\n", c.n, c.a.name.c_str(),
                robot_ticks / crw.total, robot_ticks / py.total, crw.total / py.total, crw.control * per_tick,
                py.control * per_tick, idle.control * per_tick);
    std::fflush(stdout);
  }
  return 0;
}
