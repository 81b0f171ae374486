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
//   bench_core --model swarm_forage,fordyca_2019,swarm_forage+light_occlusion --repeat 3
//                                       # the models alternately, R times each, and the CPU ratio per tick
//                                       # of each to the first (medians, min-max): alternating in one run
//                                       # keeps a noisy machine's drift out of the ratio
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/core/world/config.hpp"
#include "swarm_forage/core/world/fordyca_quirks.hpp"
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
  std::string model;  // "" = the default
  swarm_forage::FordycaQuirks quirks;
};

double cpuSeconds() {  // every thread of the process
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Result {
  double cpu = 0;  // CPU seconds of the tick loop, every thread
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
  wc.quirks = c.quirks;
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
  auto configs = swarm_forage::sharingWorld(
      {}, {(nest.min_x + nest.max_x) / 2, (nest.min_y + nest.max_y) / 2}, world.config().sight);
  configs.quirks = c.quirks;
  const auto batch = swarm_forage::makeController(c.controller, configs, seed, 0, c.n, pool);
  auto& controller = *batch;
  swarm_forage::SensorData sensors;
  swarm_forage::CommandData commands;
  swarm_forage::ControllerStatus status;
  sensors.resize(c.n);
  commands.resize(c.n);

  const double cpu0 = cpuSeconds();
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
  r.cpu = cpuSeconds() - cpu0;
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
      "core %s%s%s N=%u arena=%s threads=%u: %.2e robot-ticks/s (%llu ticks in %.2f s, CPU %.2f s), startup "
      "%.4f s, peak RSS %.0f MiB, delivered %llu, state %016llx\n",
      c.controller.c_str(), c.model.empty() ? "" : " model=", c.model.c_str(), c.n, c.arena.name.c_str(), t,
      rate, static_cast<unsigned long long>(ticks), total, r.cpu, r.startup, peakRssMiB(),
      static_cast<unsigned long long>(r.delivered), static_cast<unsigned long long>(r.state));
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
      "          [--csv FILE] [--model M[,M2...] [--repeat R]]\n"
      "  default: N=1024 in 32x16 and N=16384 in 96x48, 2000 ticks each, every controller\n",
      argv0);
  std::exit(error.empty() ? 0 : 2);
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::size_t a = 0;
  for (std::size_t b; (b = list.find(',', a)) != std::string::npos; a = b + 1)
    out.push_back(list.substr(a, b - a));
  out.push_back(list.substr(a));
  return out;
}

/// "MODEL[+quirk...]": a model and quirks on top ("" = the default model).
swarm_forage::FordycaQuirks quirksOf(const std::string& word) {
  if (word.empty()) return {};
  const std::size_t plus = word.find('+');
  std::string extra = plus == std::string::npos ? "" : word.substr(plus + 1);
  std::replace(extra.begin(), extra.end(), '+', ',');
  return swarm_forage::FordycaQuirks::parse(word.substr(0, plus), extra);
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
  std::vector<std::string> models = {""};
  uint64_t repeat = 1;
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
    else if (opt == "--model")
      models = split(value);
    else if (opt == "--repeat")
      repeat = parseCount(argv[0], opt, value);
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
    for (const auto& [n, w, h] : {std::tuple{1024u, 32.0, 16.0}, std::tuple{16384u, 96.0, 48.0}}) {
      Case c;
      c.n = n;
      c.arena = makeArena(w, h);
      sizes.push_back(c);
    }
  }
  std::vector<Case> cases;
  for (const std::string& kind : controllers)
    for (Case c : sizes) {
      c.controller = kind;
      cases.push_back(c);
    }

  try {
    for (Case c : cases) {
      // Alternately, R repeats of every model; the CPU ratios to the first model, repeat by repeat.
      std::vector<std::vector<double>> cpu(models.size());
      std::vector<uint64_t> state(models.size(), 0);
      for (uint64_t k = 0; k < repeat; ++k)
        for (std::size_t m = 0; m < models.size(); ++m) {
          c.model = models[m];
          c.quirks = quirksOf(models[m]);
          const Result r = run(c, ticks, seed, threads);
          report(c, ticks, threads, r, csv);
          if (k > 0 && r.state != state[m]) throw std::runtime_error("one seed gave two states: " + c.model);
          state[m] = r.state;
          cpu[m].push_back(r.cpu);
        }
      for (std::size_t m = 1; m < models.size(); ++m) {
        std::vector<double> q;
        for (uint64_t k = 0; k < repeat; ++k) q.push_back(cpu[m][k] / cpu[0][k]);
        std::sort(q.begin(), q.end());
        std::printf("  CPU per tick %s / %s, %s N=%u %s: %.3fx (median of %zu repeats, %.3f-%.3f)\n",
                    models[m].c_str(), models[0].c_str(), c.controller.c_str(), c.n, c.arena.name.c_str(),
                    (q[(q.size() - 1) / 2] + q[q.size() / 2]) / 2, q.size(), q.front(), q.back());
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_core: %s\n", e.what());
    return 1;
  }
  return 0;
}
