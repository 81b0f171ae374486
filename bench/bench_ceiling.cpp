// A bare-bones ceiling for bench_core: the same kind of work per robot-tick with nothing else. Neighbour
// grid, a wander turn, avoidance of bodies within reach, integration and the walls; no blocks, no
// state machine, no trigonometry (headings are unit vectors, the wander turn a fixed rotation).
// Figures from a noisy machine are comparable through their ratio to this loop run alongside.
//
//   bench_ceiling --n 16384 --arena 96x48 [--ticks 1000] [--threads T]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/core/world/spatial_grid.hpp"

namespace {
using swarm_forage::CounterRng;
using swarm_forage::RngStream;

struct Swarm {
  std::vector<double> x, y, hx, hy, nx, ny, nhx, nhy;  // n*: this tick's results (Jacobi update)
};

double run(uint32_t n, double w, double h, uint64_t ticks, unsigned threads, double& alone) {
  const double radius = 0.085, reach = 2 * radius + 0.1, speed = 0.1, dt = 0.2;
  const double turn_c = 0.99619469809174555, turn_s = 0.08715574274765817;  // a 5 degree turn
  Swarm s;
  for (auto* v : {&s.x, &s.y, &s.hx, &s.hy, &s.nx, &s.ny, &s.nhx, &s.nhy}) v->assign(n, 0);
  for (uint32_t i = 0; i < n; ++i) {
    CounterRng rng(1, RngStream::kPlacement, i, 0);
    s.x[i] = rng.uniform(radius, w - radius);
    s.y[i] = rng.uniform(radius, h - radius);
    s.hx[i] = 1;
  }
  swarm_forage::UniformGrid grid(w, h, reach + 0.01);
  swarm_forage::WorkerPool pool(threads);
  std::vector<double> sx(n), sy(n);
  const auto t0 = std::chrono::steady_clock::now();
  for (uint64_t t = 0; t < ticks; ++t) {
    grid.build(s.x.data(), s.y.data(), n);
    const auto& order = grid.order();
    for (uint32_t k = 0; k < n; ++k) {
      sx[k] = s.x[order[k]];
      sy[k] = s.y[order[k]];
    }
    const std::size_t chunk = 1024;
    pool.run((n + chunk - 1) / chunk, [&](std::size_t c, unsigned) {
      for (std::size_t k = c * chunk; k < std::min<std::size_t>(n, (c + 1) * chunk); ++k) {
        const uint32_t i = order[k];
        const double x = sx[k], y = sy[k];
        double ax = 0, ay = 0;  // away from bodies within reach
        grid.forNeighbours(x, y, [&](uint32_t j) {
          const double dx = x - sx[j], dy = y - sy[j], d2 = dx * dx + dy * dy;
          if (j != k && d2 < reach * reach) {
            ax += dx;
            ay += dy;
          }
        });
        CounterRng rng(1, RngStream::kController, i, t);
        const double side = rng.uniform() < 0.5 ? -turn_s : turn_s;
        double hx = s.hx[i] * turn_c - s.hy[i] * side, hy = s.hy[i] * turn_c + s.hx[i] * side;
        if (ax != 0 || ay != 0) {  // turn away: blend the heading with the avoidance direction
          hx += ax;
          hy += ay;
          const double len = std::sqrt(hx * hx + hy * hy);
          hx /= len;
          hy /= len;
        }
        s.nhx[i] = hx;
        s.nhy[i] = hy;
        s.nx[i] = std::min(std::max(x + speed * dt * hx, radius), w - radius);
        s.ny[i] = std::min(std::max(y + speed * dt * hy, radius), h - radius);
      }
    });
    s.x.swap(s.nx);
    s.y.swap(s.ny);
    s.hx.swap(s.nhx);
    s.hy.swap(s.nhy);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  alone = pool.percentAlone();
  return static_cast<double>(n) * static_cast<double>(ticks) / seconds;
}

}  // namespace

int main(int argc, char** argv) {
  uint32_t n = 16384;
  uint64_t ticks = 1000;
  unsigned threads = 0;
  double w = 96, h = 48;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string opt = argv[i], value = argv[i + 1];
    if (opt == "--n")
      n = static_cast<uint32_t>(std::strtoul(value.c_str(), nullptr, 10));
    else if (opt == "--ticks")
      ticks = std::strtoull(value.c_str(), nullptr, 10);
    else if (opt == "--threads")
      threads = static_cast<unsigned>(std::strtoul(value.c_str(), nullptr, 10));
    else if (opt == "--arena" && std::sscanf(value.c_str(), "%lfx%lf", &w, &h) == 2)
      continue;
    else {
      std::fprintf(stderr, "usage: %s [--n N] [--arena WxH] [--ticks K] [--threads T]\n", argv[0]);
      return 2;
    }
  }
  if (n == 0 || ticks == 0 || w <= 1 || h <= 1) {
    std::fprintf(stderr, "bench_ceiling: --n, --ticks must be positive and the arena larger than 1x1 m\n");
    return 2;
  }
  double alone = 0;
  const double rate = run(n, w, h, ticks, threads, alone);
  std::printf(
      "ceiling N=%u arena=%gx%g threads=%u: %.3e robot-ticks/s, %.0f %% of jobs on one thread (cores "
      "contended)\n",
      n, w, h, threads == 0 ? swarm_forage::WorkerPool::cores() : threads, rate, alone);
  return 0;
}
