// Final performance per swarm size, headless, with the project's own e and Z (docs/FIDELITY.md):
// for each controller and N = 1, 2, 4, ... up to --max-n, `--seeds` runs of `--ticks` ticks; prints one
// markdown row per (controller, N): mean final P (min-max over seeds), e against N/2 and mean Z.
// --trace prints, for one run (--n N), every sample: P, robots carrying, in avoidance and stalled (not
// moved 1 cm in the last 50 ticks), by state.
//
// --model NAME (swarm_forage, fordyca_2019) and --quirks a,b run both modes under FORDYCA 2019's quirks. The
// ablation of the quirks is a study of its own, through `sweep` (`make ablation`, docs/FIDELITY.md).
//
//   bench_fidelity --arena 32x16 --max-n 1024 --seeds 3
//   bench_fidelity --arena 64x32 --controllers dpo --n 1024 --trace --model fordyca_2019
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fidelity_common.hpp"
#include "swarm_forage/core/metrics/run_library.hpp"

namespace {
using namespace swarm_forage;
using fidelity::arenaNamed;
using fidelity::Stalls;

RunSeries runOnce(const ArenaConfig& arena, const std::string& kind, uint32_t n, uint32_t seed,
                  uint64_t ticks, uint32_t interval, bool trace, const FordycaQuirks& quirks) {
  WorldConfig c;
  c.arena = arena;
  c.n_robots = n;
  c.seed = seed;
  c.quirks = quirks;  // the world's and the controllers' quirks from the one parse
  ControllerConfigs configs;
  configs.quirks = quirks;
  Simulation sim(c, kind, configs);
  RunSeriesBuilder builder(interval, n);
  Stalls stalls;
  for (uint64_t t = 0; t < ticks; ++t) {
    const StepResult r = sim.step();
    const auto sample =
        builder.add(t, r.delivered, sim.world().delivered(), sim.status().in_avoidance, t + 1 == ticks, 0.0);
    const uint32_t stalled = trace ? stalls.count(sim.world().robots(), t) : 0;
    if (trace && sample) {
      std::printf("tick %6llu  P %4llu  carrying %5u  avoiding %5u  stalled %5u ",
                  static_cast<unsigned long long>(t),
                  static_cast<unsigned long long>(sim.world().delivered()), sim.world().carrying(),
                  sim.status().in_avoidance, stalled);
      const ControllerStatus& st = sim.status();
      for (std::size_t k = 0; k < st.state_names.size(); ++k)
        if (st.state_counts[k]) std::printf(" %s %u", st.state_names[k].c_str(), st.state_counts[k]);
      if (sim.world().config().cache.enabled)
        std::printf("  cache %s %zu", sim.world().cache().exists() ? "yes" : "no",
                    sim.world().cache().size());
      std::printf("  H %u C %u\n", st.tasks.harvesters, st.tasks.collectors);
      std::fflush(stdout);
    }
  }
  return builder.series();
}
}  // namespace

namespace {
[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "bench_fidelity: %s\nusage: bench_fidelity [--arena 32x16|64x32|96x48] [--controllers a,b] "
               "[--max-n N] [--n N] [--seeds K] [--ticks T] [--trace] [--model swarm_forage|fordyca_2019] "
               "[--quirks a,b]\n",
               why.c_str());
  std::exit(2);
}

uint64_t number(const std::string& opt, const char* v, uint64_t low) {
  char* end = nullptr;
  const unsigned long long x = std::strtoull(v, &end, 10);
  if (*v == '\0' || *end != '\0' || *v == '-' || x < low)
    usage(opt + " must be a whole number >= " + std::to_string(low) + " (got '" + v + "')");
  return x;
}
}  // namespace

int main(int argc, char** argv) {
  std::string arena_name = "32x16", controllers = "crw,dpo,gp_dpo", model = "swarm_forage", extra_quirks;
  uint32_t max_n = 1024, seeds = 3, one_n = 0, interval = 1000;
  uint64_t ticks = 50000;
  bool trace = false;
  for (int i = 1; i < argc; ++i) {
    const std::string opt = argv[i];
    if (opt == "--trace") {
      trace = true;
      continue;
    }
    if (opt == "--ablate")
      usage("--ablate is gone: the ablation runs through sweep (make ablation, docs/FIDELITY.md)");
    if (i + 1 >= argc) usage(opt + " needs a value");
    const char* v = argv[++i];
    if (opt == "--arena")
      arena_name = v;
    else if (opt == "--controllers")
      controllers = v;
    else if (opt == "--max-n")
      max_n = static_cast<uint32_t>(number(opt, v, 1));
    else if (opt == "--n")
      one_n = static_cast<uint32_t>(number(opt, v, 1));
    else if (opt == "--seeds")
      seeds = static_cast<uint32_t>(number(opt, v, 1));
    else if (opt == "--ticks")
      ticks = number(opt, v, 1);
    else if (opt == "--model")
      model = v;
    else if (opt == "--quirks")
      extra_quirks = v;
    else
      usage("unknown option " + opt);
  }
  FordycaQuirks quirks;
  try {
    quirks = FordycaQuirks::parse(model, extra_quirks);
  } catch (const ParameterError& e) {
    usage(std::string(e.what()).replace(0, 1, "--"));  // "~model ..." -> "--model ..."
  }
  const ArenaConfig arena = arenaNamed(arena_name);
  std::vector<std::string> kinds;
  std::stringstream list(controllers);
  for (std::string k; std::getline(list, k, ',');) kinds.push_back(k);
  if (kinds.empty()) usage("--controllers is empty");
  if (trace) {
    if (quirks.any()) std::printf("# model %s, quirks %s\n", model.c_str(), quirks.names().c_str());
    runOnce(arena, kinds.front(), one_n ? one_n : max_n, 1, ticks, interval, true, quirks);
    return 0;
  }
  if (quirks.any()) std::printf("Model %s, quirks %s.\n\n", model.c_str(), quirks.names().c_str());
  std::printf(
      "| arena | controller | N | final P (mean, min-max over %u seeds) | e vs N/2 | mean Z "
      "|\n|---|---|---|---|---|---|\n",
      seeds);
  for (const std::string& kind : kinds) {
    RunLibrary library;
    std::map<uint32_t, std::vector<double>> finals;
    for (uint32_t n = 1; n <= max_n; n *= 2)
      for (uint32_t s = 1; s <= seeds; ++s) {
        RunRecord r;
        r.key.controller = kind;
        r.key.arena = arena.name;
        r.key.swarm_size = n;
        r.seed = s;
        r.source = "seed " + std::to_string(s);
        r.series = runOnce(arena, kind, n, s, ticks, interval, false, quirks);
        finals[n].push_back(r.series.P.empty() ? 0.0 : r.series.P.back());
        library.add(r);
        std::fprintf(stderr, "  %s N=%u seed %u: P=%g\n", kind.c_str(), n, s, finals[n].back());
      }
    for (const auto& [key, group] : library.groups()) {
      const RunEvaluation ev = evaluateRun(library, key, group.mean, true, Definitions::kPaper);
      const auto& f = finals[key.swarm_size];
      double mean = 0;
      for (double p : f) mean += p / f.size();
      char e[32] = "n/a", z[32] = "n/a";
      if (ev.scalability_status.valid) std::snprintf(e, sizeof e, "%.3f", ev.scalability.e.value);
      if (ev.self_organization_status.valid)
        std::snprintf(z, sizeof z, "%.3f", ev.self_organization.z_mean.value);
      std::printf("| %s | %s | %u | %.1f (%g-%g) | %s | %s |\n", arena.name.c_str(), kind.c_str(),
                  key.swarm_size, mean, *std::min_element(f.begin(), f.end()),
                  *std::max_element(f.begin(), f.end()), e, z);
      std::fflush(stdout);
    }
  }
  return 0;
}
