// Headless core throughput: World + one controller batch covering every robot, looping
// sense -> controller step -> world.step, without ROS. Reports robot-ticks per second, the start-up
// time (World construction: validation, block and robot placement) and how the tick splits between
// sensing, the controller and the world step.
//
//   bench_core                          # the two standard cases (N=1,024 32x16; N=16,384 96x48)
//                                       # for each controller (crw, dpo, gp_dpo)
//   bench_core --controller dpo         # one controller
//   bench_core --ticks 5000
//   bench_core --n 4096 --arena 64x32   # one custom case
//   bench_core --threads 1              # worker threads (default 0: one per core)
//   bench_core --csv FILE               # also append one CSV row per case (see bench/bench_all.py)
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/core/world/config.hpp"
#include "swarm_forage/core/world/sensing.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using swarm_forage::ArenaConfig;

double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

struct Case {
  uint32_t n = 0;
  ArenaConfig arena;
  std::string controller = "crw";
};

struct Result {
  double startup = 0, sense = 0, control = 0, step = 0;
  double alone = 0;  // the pool's jobs run on one thread because the cores were contended, in percent
  uint64_t delivered = 0, state = 0;
  double total() const { return sense + control + step; }
};

/// The paper's arenas keep their block counts (50 / 200 / 460); others scale 50 blocks per 32x16 m.
ArenaConfig makeArena(double width, double height) {
  ArenaConfig a;
  char name[64];
  std::snprintf(name, sizeof name, "%gx%g", width, height);
  a.name = name;
  a.width = width;
  a.height = height;
  if (width == 32 && height == 16)
    a.n_blocks = 50;
  else if (width == 64 && height == 32)
    a.n_blocks = 200;
  else if (width == 96 && height == 48)
    a.n_blocks = 460;
  else
    a.n_blocks = static_cast<uint32_t>(std::max(1.0, 50.0 * width * height / (32.0 * 16.0)));
  return a;
}

Result run(const Case& c, uint64_t ticks, uint32_t seed, unsigned threads) {
  swarm_forage::WorldConfig wc;
  wc.arena = c.arena;
  wc.n_robots = c.n;
  wc.seed = seed;
  Result r;
  const auto t0 = Clock::now();
  swarm_forage::World world(swarm_forage::configuredFor(wc, c.controller));
  r.startup = seconds(t0, Clock::now());
  const auto pool = std::make_shared<swarm_forage::WorkerPool>(threads);
  world.setPool(pool);

  const swarm_forage::Rect nest = c.arena.nest();
  const auto configs = swarm_forage::sharingWorld(
      {}, {(nest.min_x + nest.max_x) / 2, (nest.min_y + nest.max_y) / 2}, world.config().sight);
  const auto batch = swarm_forage::makeController(c.controller, configs, seed, 0, c.n, pool);
  auto& controller = *batch;
  swarm_forage::SensorData sensors;
  swarm_forage::CommandData commands;
  swarm_forage::ControllerStatus status;
  sensors.resize(c.n);
  commands.resize(c.n);

  for (uint64_t k = 0; k < ticks; ++k) {
    const auto a = Clock::now();
    world.sense(sensors);
    const auto b = Clock::now();
    controller.step(world.tick(), sensors, commands, status);
    const auto d = Clock::now();
    world.step(commands, 0.0);
    const auto e = Clock::now();
    r.sense += seconds(a, b);
    r.control += seconds(b, d);
    r.step += seconds(d, e);
  }
  r.delivered = world.delivered();
  r.alone = pool->percentAlone();
  // A hash of the final bodies: equal for every thread count (the determinism the tests check).
  uint64_t h = 1469598103934665603ULL;
  const auto mixIn = [&](const void* p, std::size_t bytes) {
    for (std::size_t k = 0; k < bytes; ++k)
      h = (h ^ static_cast<const unsigned char*>(p)[k]) * 1099511628211ULL;
  };
  const auto& b = world.robots();
  mixIn(b.x.data(), b.x.size() * sizeof(double));
  mixIn(b.y.data(), b.y.size() * sizeof(double));
  mixIn(b.theta.data(), b.theta.size() * sizeof(double));
  r.state = h;
  return r;
}

double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // kilobytes on Linux
}

void report(const Case& c, uint64_t ticks, unsigned threads, const Result& r, const std::string& csv) {
  const double total = r.total();
  const double rate = total > 0 ? static_cast<double>(c.n) * static_cast<double>(ticks) / total : 0.0;
  const unsigned t = threads == 0 ? swarm_forage::WorkerPool::cores() : threads;
  std::printf(
      "core %s N=%u arena=%s threads=%u: %.2e robot-ticks/s (%llu ticks in %.2f s), startup %.4f s, peak RSS "
      "%.0f MiB, delivered %llu, state %016llx\n",
      c.controller.c_str(), c.n, c.arena.name.c_str(), t, rate, static_cast<unsigned long long>(ticks), total,
      r.startup, peakRssMiB(), static_cast<unsigned long long>(r.delivered),
      static_cast<unsigned long long>(r.state));
  if (!csv.empty()) {
    FILE* f = std::fopen(csv.c_str(), "a");
    if (f == nullptr) throw std::runtime_error("--csv " + csv + " cannot be appended to");
    std::fprintf(f, "headless,%s,%u,%s,%u,%llu,%.6g,%.6g,%.1f,%.6f,%016llx\n", c.controller.c_str(), c.n,
                 c.arena.name.c_str(), t, static_cast<unsigned long long>(ticks), rate,
                 rate > 0 ? 1e9 / rate : 0.0, peakRssMiB(), r.startup,
                 static_cast<unsigned long long>(r.state));
    std::fclose(f);
  }
  const double pct = total > 0 ? 100.0 / total : 0.0;
  std::printf(
      "  split: sense %.1f %%, controller %.1f %%, world.step %.1f %%; %.0f %% of jobs on one thread "
      "(cores contended)\n",
      r.sense * pct, r.control * pct, r.step * pct, r.alone);
  std::fflush(stdout);
}

[[noreturn]] void usage(const char* argv0, const std::string& error) {
  if (!error.empty()) std::fprintf(stderr, "%s: %s\n", argv0, error.c_str());
  std::fprintf(
      stderr,
      "usage: %s [--ticks K] [--seed S] [--controller crw|dpo|gp_dpo] [--n N --arena WxH] [--threads T]\n"
      "          [--csv FILE]\n"
      "  default: N=1024 in 32x16 and N=16384 in 96x48, 2000 ticks each, every controller\n",
      argv0);
  std::exit(error.empty() ? 0 : 2);
}

uint64_t parseCount(const char* argv0, const std::string& opt, const std::string& value) {
  char* end = nullptr;
  const unsigned long long v = std::strtoull(value.c_str(), &end, 10);
  if (value.empty() || value[0] == '-' || *end != '\0' || v == 0 || v > 0xffffffffULL)
    usage(argv0, opt + " needs a positive integer (got '" + value + "')");
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  uint64_t ticks = 2000;
  unsigned threads = 0;
  std::string csv;
  uint32_t seed = 1;
  uint64_t custom_n = 0;
  std::string custom_arena;
  std::vector<std::string> controllers = swarm_forage::controllerNames();
  for (int i = 1; i < argc; ++i) {
    const std::string opt = argv[i];
    if (opt == "-h" || opt == "--help") usage(argv[0], "");
    if (i + 1 >= argc) usage(argv[0], opt + " needs a value");
    const std::string value = argv[++i];
    if (opt == "--ticks")
      ticks = parseCount(argv[0], opt, value);
    else if (opt == "--seed")
      seed = static_cast<uint32_t>(std::strtoul(value.c_str(), nullptr, 10));
    else if (opt == "--n")
      custom_n = parseCount(argv[0], opt, value);
    else if (opt == "--arena")
      custom_arena = value;
    else if (opt == "--threads")
      threads = static_cast<unsigned>(std::strtoul(value.c_str(), nullptr, 10));
    else if (opt == "--csv")
      csv = value;
    else if (opt == "--controller")
      controllers = {value};
    else
      usage(argv[0], "unknown option " + opt);
  }

  std::vector<Case> sizes;
  if (custom_n > 0 || !custom_arena.empty()) {
    Case c;
    c.n = static_cast<uint32_t>(custom_n > 0 ? custom_n : 1024);
    double w = 32, h = 16;
    if (!custom_arena.empty()) {
      char x = 0;
      char extra = 0;
      if (std::sscanf(custom_arena.c_str(), "%lf%c%lf%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
        usage(argv[0], "--arena needs WxH in metres, e.g. 64x32 (got '" + custom_arena + "')");
    }
    c.arena = makeArena(w, h);
    sizes.push_back(c);
  } else {
    sizes.push_back({1024, makeArena(32, 16)});
    sizes.push_back({16384, makeArena(96, 48)});
  }
  std::vector<Case> cases;
  for (const std::string& kind : controllers)
    for (Case c : sizes) {
      c.controller = kind;
      cases.push_back(c);
    }

  try {
    for (const Case& c : cases) report(c, ticks, threads, run(c, ticks, seed, threads), csv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_core: %s\n", e.what());
    return 1;
  }
  return 0;
}
