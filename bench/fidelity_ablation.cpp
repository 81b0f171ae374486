// bench_fidelity --ablate: FORDYCA 2019's quirks one at a time (docs/FIDELITY.md, "FORDYCA as it ran").
// Arms: DPO 64x32 N=1024, DPO 96x48 N=2048, CRW 96x48 N=8192. Rows: today's model, fordyca_2019, each quirk
// alone on top of today's model (quirkList(): a new quirk joins by itself), and fordyca_2019 plus each quirk
// it leaves out. Every finished run is one line of the cache (CSV), keyed by arm, row, seed and the run's
// identity (model version, world and controller constants with their quirks, arena, N, ticks): a rerun
// reuses it, and a run whose identity changed is run again. Each line also names the code that made it (git
// description): the table lists them, and a run reused from other code is warned about, since a quirk's
// implementation can change while its name, and so the identity, stays.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "fidelity_common.hpp"
#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/metrics/swarm_metrics.hpp"
#include "swarm_forage/core/run/condition_series.hpp"
#include "swarm_forage/core/run/model_version.hpp"
#include "swarm_forage/core/run/run_records.hpp"

namespace swarm_forage {
const char* codeDescription();  // build_info.cpp, made at every build
}  // namespace swarm_forage

namespace swarm_forage::fidelity {
namespace {

struct Arm {
  std::string name, kind, arena;
  uint32_t n;
  std::string title;
};

const std::vector<Arm>& arms() {
  static const std::vector<Arm> list{{"dpo_64x32_n1024", "dpo", "64x32", 1024, "DPO 64×32 N=1,024"},
                                     {"dpo_96x48_n2048", "dpo", "96x48", 2048, "DPO 96×48 N=2,048"},
                                     {"crw_96x48_n8192", "crw", "96x48", 8192, "CRW 96×48 N=8,192"}};
  return list;
}

struct Row {
  std::string name;
  FordycaQuirks quirks;
};

/// swarm_forage, fordyca_2019, each quirk alone, fordyca_2019 + each quirk it leaves out.
std::vector<Row> rows() {
  std::vector<Row> out{{"swarm_forage", FordycaQuirks::parse("swarm_forage", "")},
                       {"fordyca_2019", FordycaQuirks::parse("fordyca_2019", "")}};
  for (const QuirkInfo& q : quirkList())
    out.push_back({q.name, FordycaQuirks::parse("swarm_forage", q.name)});
  for (const QuirkInfo& q : quirkList())
    if (!q.fordyca_2019)
      out.push_back({"fordyca_2019+" + std::string(q.name), FordycaQuirks::parse("fordyca_2019", q.name)});
  return out;
}

template <class T>
std::vector<T> selected(const std::vector<T>& all, const std::string& wanted, const char* option) {
  if (wanted.empty()) return all;
  std::vector<T> out;
  std::stringstream list(wanted);
  for (std::string w; std::getline(list, w, ',');) {
    if (w.empty()) continue;
    auto it = std::find_if(all.begin(), all.end(), [&](const T& x) { return x.name == w; });
    if (it == all.end()) {
      std::string valid;
      for (const T& x : all) valid += (valid.empty() ? "" : ", ") + x.name;
      throw ParameterError(std::string(option) + ": '" + w +
                           "' is unknown; valid (comma-separated): " + valid);
    }
    if (std::none_of(out.begin(), out.end(), [&](const T& x) { return x.name == w; })) out.push_back(*it);
  }
  return out;
}

struct Setup {
  WorldConfig world;
  ControllerConfigs controllers;
};

/// The world's and the controllers' quirks from the one parse of the row.
Setup setupOf(const Arm& arm, const Row& row, uint32_t seed) {
  Setup s;
  s.world.arena = arenaNamed(arm.arena);
  s.world.n_robots = arm.n;
  s.world.seed = seed;
  s.world.quirks = row.quirks;
  s.controllers.quirks = row.quirks;
  return s;
}

/// What the run is, seed apart: the core's run identity (as a recorded run of it would carry, without a
/// condition) and the model version that computes it.
std::string identityText(const Arm& arm, const Row& row, uint64_t ticks) {
  const Setup s = setupOf(arm, row, 1);
  RunDescription d;
  d.controller = arm.kind;
  d.world = configuredFor(s.world, arm.kind);
  d.ticks = ticks;
  d.controller_constants = describeConstants(arm.kind, s.controllers);
  d.condition = conditionAt(Condition{}, 0, d.world.ticks_per_second);
  d.fixed = true;
  return "model_version=" + std::to_string(kModelVersion) + " identity=" + d.identity();
}

struct Outcome {
  double P = 0;
  uint32_t stalled = 0;
  std::string code;  // the code that made the run
};

struct Job {
  const Arm* arm;
  const Row* row;
  uint32_t seed;
  std::string identity;
};

Outcome runOne(const Job& job, uint64_t ticks, unsigned threads, std::atomic<uint64_t>& robot_ticks) {
  const Setup s = setupOf(*job.arm, *job.row, job.seed);
  if (s.world.quirks != s.controllers.quirks) std::abort();  // one parse for both sides
  Simulation sim(s.world, job.arm->kind, s.controllers, threads);
  Stalls stalls;
  Outcome out;
  for (uint64_t t = 0; t < ticks; ++t) {
    sim.step();
    out.stalled = stalls.count(sim.world().robots(), t);
    if (t % 500 == 499 || t + 1 == ticks) robot_ticks += uint64_t{job.arm->n} * (t % 500 + 1);
  }
  out.P = static_cast<double>(sim.world().delivered());
  return out;
}

using CacheKey = std::tuple<std::string, std::string, uint32_t, std::string>;  // arm, row, seed, identity

std::map<CacheKey, Outcome> readCache(const std::string& path) {
  std::map<CacheKey, Outcome> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line.rfind("arm,", 0) == 0) continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    // arm,row,seed,model_version,quirks,identity,ticks,final_P,stalled,seconds,code
    if (f.size() != 11) continue;  // a line cut short by a stop
    try {
      out[{f[0], f[1], static_cast<uint32_t>(std::stoul(f[2])), f[5]}] = {
          std::stod(f[7]), static_cast<uint32_t>(std::stoul(f[8])), f[10]};
    } catch (const std::exception&) {
    }
  }
  return out;
}

std::string clock(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  return buf;
}

struct Stats {
  std::size_t n = 0;
  double mean = 0, sd = 0, lo = 0, hi = 0, min = 0, max = 0;
};

Stats stats(const std::vector<double>& v) {
  Stats s;
  s.n = v.size();
  if (v.empty()) return s;
  for (double x : v) s.mean += x / v.size();
  for (double x : v) s.sd += (x - s.mean) * (x - s.mean);
  s.sd = v.size() > 1 ? std::sqrt(s.sd / (v.size() - 1)) : 0.0;
  const double half =
      v.size() > 1 ? studentT95(static_cast<uint32_t>(v.size() - 1)) * s.sd / std::sqrt(v.size()) : 0;
  s.lo = std::max(0.0, s.mean - half), s.hi = s.mean + half;
  s.min = *std::min_element(v.begin(), v.end()), s.max = *std::max_element(v.begin(), v.end());
  return s;
}

std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0, double e = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b, c, d, e);
  return buf;
}

/// Claim (d): mean P of DPO 96x48 N=2048 over mean P of CRW 96x48 N=8192, with a 95 % interval by the delta
/// method (Welch-Satterthwaite degrees of freedom), against 1 +- 0.15.
std::string claimD(const Stats& dpo, const Stats& crw) {
  if (dpo.n == 0 || crw.n == 0) return "not run | not run";
  if (crw.mean <= 0) return "n/a (CRW P = 0) | n/a";
  const double r = dpo.mean / crw.mean;
  if (dpo.n < 2 || crw.n < 2 || dpo.mean <= 0) return fmt("%.3f | n/a (1 seed)", r);
  const double va = dpo.sd * dpo.sd / dpo.n / (dpo.mean * dpo.mean),
               vb = crw.sd * crw.sd / crw.n / (crw.mean * crw.mean);
  double dof = dpo.n + crw.n - 2.0;
  if (va + vb > 0) dof = (va + vb) * (va + vb) / (va * va / (dpo.n - 1) + vb * vb / (crw.n - 1));
  const double half =
      studentT95(static_cast<uint32_t>(std::max(1.0, std::floor(dof)))) * r * std::sqrt(va + vb);
  const double lo = std::max(0.0, r - half), hi = r + half;
  const char* verdict = lo >= 0.85 && hi <= 1.15 ? "holds" : (hi < 0.85 || lo > 1.15) ? "fails" : "undecided";
  return fmt("%.3f [%.3f, %.3f]", r, lo, hi) + " | " + verdict;
}

void printTable(const std::vector<Arm>& sel_arms, const std::vector<Row>& sel_rows, const AblationOptions& o,
                const std::map<CacheKey, Outcome>& cache,
                const std::map<std::string, std::string>& identity) {
  std::printf("Made by `%s` (%u seeds, 1..%u; %llu ticks = %.0f s; cache %s).\n\n", o.command.c_str(),
              o.seeds, o.seeds, static_cast<unsigned long long>(o.ticks), o.ticks / 5.0, o.cache.c_str());
  std::printf(
      "Final P: mean [95 %% t-interval over seeds, clipped at 0] (min-max); stalled: robots that have not "
      "moved 1 cm in the last 50 ticks at T, mean (min-max). (d): mean P of DPO 96×48 N=2,048 over CRW "
      "96×48 N=8,192 [95 %% interval, delta method]; holds when the interval lies in [0.85, 1.15].\n\n");
  std::string head = "| row |", rule = "|---|";
  for (const Arm& a : sel_arms) head += " " + a.title + ": final P | stalled at T |", rule += "---|---|";
  const bool d = std::any_of(sel_arms.begin(), sel_arms.end(), [](const Arm& a) { return a.n == 2048; }) &&
                 std::any_of(sel_arms.begin(), sel_arms.end(), [](const Arm& a) { return a.n == 8192; });
  if (d) head += " (d) DPO 2,048 / CRW 8,192 | (d) |", rule += "---|---|";
  std::printf("%s\n%s\n", head.c_str(), rule.c_str());
  std::map<std::string, int> codes;
  for (const Row& row : sel_rows) {
    std::string line = "| " + row.name + " |";
    std::map<std::string, Stats> P;
    for (const Arm& a : sel_arms) {
      std::vector<double> p, st;
      for (uint32_t s = 1; s <= o.seeds; ++s) {
        auto it = cache.find({a.name, row.name, s, identity.at(a.name + "/" + row.name)});
        if (it == cache.end()) continue;
        p.push_back(it->second.P), st.push_back(it->second.stalled);
        ++codes[it->second.code];
      }
      const Stats sp = stats(p), ss = stats(st);
      P[a.name] = sp;
      if (p.empty()) {
        line += " not run | not run |";
        continue;
      }
      const std::string part = p.size() < o.seeds ? fmt(", %.0f of %.0f seeds", p.size(), o.seeds) : "";
      line += fmt(" %.1f [%.1f, %.1f] (%.0f-%.0f)", sp.mean, sp.lo, sp.hi, sp.min, sp.max) + part + " |";
      line += fmt(" %.1f (%.0f-%.0f) |", ss.mean, ss.min, ss.max);
    }
    if (d) line += " " + claimD(P["dpo_96x48_n2048"], P["crw_96x48_n8192"]) + " |";
    std::printf("%s\n", line.c_str());
  }
  std::string made;
  for (const auto& [c, n] : codes) made += (made.empty() ? "" : ", ") + c + fmt(" (%.0f runs)", n);
  std::printf("\nThe runs were made by the code %s.\n", made.empty() ? "(none)" : made.c_str());
  std::fflush(stdout);
}

}  // namespace

int runAblation(const AblationOptions& o) {
  std::vector<Arm> sel_arms;
  std::vector<Row> all_rows = rows(), sel_rows;
  try {
    sel_arms = selected(arms(), o.arms, "--arms");
    sel_rows = selected(all_rows, o.rows, "--rows");
  } catch (const ParameterError& e) {
    std::fprintf(stderr, "bench_fidelity: %s\n", e.what());
    return 2;
  }
  std::map<std::string, std::string> identity;  // arm/row -> digest
  for (const Arm& a : sel_arms)
    for (const Row& r : sel_rows)
      identity[a.name + "/" + r.name] = contentDigest(identityText(a, r, o.ticks));
  std::map<CacheKey, Outcome> cache = readCache(o.cache);
  std::string code = codeDescription();
  std::replace(code.begin(), code.end(), ',', ';');
  std::vector<Job> jobs;
  for (const Arm& a : sel_arms)
    for (const Row& r : sel_rows)
      for (uint32_t s = 1; s <= o.seeds; ++s) {
        const std::string& id = identity[a.name + "/" + r.name];
        if (!cache.count({a.name, r.name, s, id})) jobs.push_back({&a, &r, s, id});
      }
  const std::size_t total = sel_arms.size() * sel_rows.size() * o.seeds, reused = total - jobs.size();
  std::map<std::string, int> other;  // cached runs of the selection made by other code
  for (const auto& [key, out] : cache)
    if (out.code != code && identity.count(std::get<0>(key) + "/" + std::get<1>(key)) &&
        identity.at(std::get<0>(key) + "/" + std::get<1>(key)) == std::get<3>(key) &&
        std::get<2>(key) <= o.seeds)
      ++other[out.code];
  for (const auto& [c, n] : other)
    std::fprintf(stderr,
                 "ablate: warning: %d cached runs were made by the code %s, not %s: reused (equal identity); "
                 "remove their lines from %s if a quirk's implementation changed since\n",
                 n, c.c_str(), code.c_str(), o.cache.c_str());
  if (!o.table_only && !jobs.empty()) {
    const std::filesystem::path dir = std::filesystem::path(o.cache).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir);
    if (!std::filesystem::exists(o.cache))
      std::ofstream(o.cache)
          << "arm,row,seed,model_version,quirks,identity,ticks,final_P,stalled,seconds,code\n";
    // The biggest first, so that the last runs to finish are short ones.
    std::stable_sort(jobs.begin(), jobs.end(),
                     [](const Job& a, const Job& b) { return a.arm->n > b.arm->n; });
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    const unsigned threads = o.threads ? o.threads : cores;
    const unsigned workers = std::min<unsigned>(threads, static_cast<unsigned>(jobs.size()));
    const unsigned per_run = std::max(1u, threads / workers);
    uint64_t all_robot_ticks = 0;
    for (const Job& j : jobs) all_robot_ticks += uint64_t{j.arm->n} * o.ticks;
    std::fprintf(
        stderr, "ablate: %zu runs (%zu of %zu cached in %s), %.3g robot-ticks, %u at a time x %u thread(s)\n",
        jobs.size(), reused, total, o.cache.c_str(), static_cast<double>(all_robot_ticks), workers, per_run);
    std::atomic<std::size_t> next{0}, done{0};
    std::atomic<uint64_t> robot_ticks{0};
    std::mutex m;
    std::condition_variable cv;
    const auto start = std::chrono::steady_clock::now();
    const auto elapsed = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    const auto progress = [&](const std::string& what) {
      const double e = elapsed(), rate = robot_ticks / std::max(e, 1e-9);
      const double eta =
          rate > 0 ? (all_robot_ticks - std::min<uint64_t>(robot_ticks, all_robot_ticks)) / rate : 0;
      std::fprintf(stderr, "ablate: %zu/%zu runs done, elapsed %s, ETA %s (%.3g robot-ticks/s)%s\n",
                   done.load(), jobs.size(), clock(e).c_str(), rate > 0 ? clock(eta).c_str() : "?", rate,
                   what.c_str());
    };
    std::vector<std::thread> pool;
    for (unsigned w = 0; w < workers; ++w)
      pool.emplace_back([&] {
        for (std::size_t k; (k = next++) < jobs.size();) {
          const Job& j = jobs[k];
          const auto t0 = std::chrono::steady_clock::now();
          const Outcome out = runOne(j, o.ticks, per_run, robot_ticks);
          const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          std::lock_guard<std::mutex> lock(m);
          std::string quirks = j.row->quirks.names();
          std::replace(quirks.begin(), quirks.end(), ',', ';');
          std::ofstream(o.cache, std::ios::app)
              << j.arm->name << ',' << j.row->name << ',' << j.seed << ',' << kModelVersion << ','
              << (quirks.empty() ? "none" : quirks) << ',' << j.identity << ',' << o.ticks << ','
              << fmt("%.0f", out.P) << ',' << out.stalled << ',' << fmt("%.1f", secs) << ',' << code << '\n'
              << std::flush;
          cache[{j.arm->name, j.row->name, j.seed, j.identity}] = {out.P, out.stalled, code};
          ++done;
          progress("; " + j.arm->name + " " + j.row->name + " seed " + std::to_string(j.seed) +
                   fmt(": P %.0f, %.0f stalled, %.0f s", out.P, out.stalled, secs));
          cv.notify_all();
        }
      });
    {
      std::unique_lock<std::mutex> lock(m);
      while (done < jobs.size())
        if (!cv.wait_for(lock, std::chrono::seconds(30), [&] { return done >= jobs.size(); })) progress("");
    }
    for (std::thread& t : pool) t.join();
  } else if (jobs.empty()) {
    std::fprintf(stderr, "ablate: all %zu runs cached in %s\n", total, o.cache.c_str());
  } else {
    std::fprintf(stderr, "ablate: --table-only: %zu of %zu runs not in %s (shown as \"not run\")\n",
                 jobs.size(), total, o.cache.c_str());
  }
  printTable(sel_arms, sel_rows, o, cache, identity);
  return 0;
}

}  // namespace swarm_forage::fidelity
