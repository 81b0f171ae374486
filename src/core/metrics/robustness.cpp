#include "swarm_forage/core/metrics/robustness.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "swarm_forage/core/metrics/dtw.hpp"
#include "swarm_forage/core/metrics/run_library.hpp"

namespace swarm_forage {

namespace {
MetricValue ok(double v) { return {v, true, {}}; }
MetricValue bad(std::string reason) { return {0.0, false, std::move(reason)}; }

/// The whole of `text` as a finite number >= 0, or nullopt.
std::optional<double> rate(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v) || v < 0) return std::nullopt;
  return v;
}

void append(std::string& to, const std::string& word) { to += (to.empty() ? "" : " ") + word; }
}  // namespace

std::string robustnessUnavailable(Definitions defs) {
  return defs == Definitions::kAuthorsCode2019 ? "authors_code_2019: the authors' 2019 code has no "
                                                 "robustness measure (definitions authors_code "
                                                 "uses their later code)"
                                               : "";
}

RobustnessWords robustnessWords(const std::string& world_constants) {
  RobustnessWords w;
  std::istringstream in(world_constants);
  std::string word;
  while (in >> word) {
    const std::size_t eq = word.find('=');
    const std::string name = word.substr(0, eq), value = eq == std::string::npos ? "" : word.substr(eq + 1);
    const bool noise = name.rfind("noise/", 0) == 0, population = name.rfind("population/", 0) == 0;
    if (!noise) append(w.without_noise, word);
    if (!population) append(w.without_population, word);
    if (noise) {
      append(w.noise, word);
      const std::size_t colon = value.rfind(':');  // model:level, or a bare level (ground)
      const auto level = rate(colon == std::string::npos ? value : value.substr(colon + 1));
      if (!level && w.problem.empty()) w.problem = "cannot read the noise level of '" + word + "'";
      if (level && *level > w.noise_level) w.noise_level = *level;
    } else if (population) {
      const auto v = rate(value);
      const std::string key = name.substr(11);
      double* field = key == "death"         ? &w.population.death
                      : key == "birth"       ? &w.population.birth
                      : key == "malfunction" ? &w.population.malfunction
                      : key == "repair"      ? &w.population.repair
                                             : nullptr;
      if (!v || (!field && key != "max_size")) {
        if (w.problem.empty()) w.problem = "cannot read the population word '" + word + "'";
      } else if (field) {
        *field = *v;
      } else {
        w.population.max_size = static_cast<uint32_t>(*v);
      }
    }
  }
  return w;
}

double logisticSpread(double x) { return std::tanh(x / 2.0); }

SaaRobustness saaRobustness(const RunSeries& reference, const RunSeries& run, Definitions defs,
                            std::optional<std::size_t> band) {
  SaaRobustness out;
  const auto fail = [&out](const std::string& why) {
    out.distance = out.normalized = bad(why);
    return out;
  };
  if (defs == Definitions::kAuthorsCode2019) return fail(robustnessUnavailable(defs));
  if (run.P.empty()) return fail("run has no samples");
  if (reference.interval != run.interval)
    return fail("reference run is sampled every " + std::to_string(reference.interval) +
                " ticks, run every " + std::to_string(run.interval));
  if (reference.P.size() != run.P.size())
    return fail("reference run has " + std::to_string(reference.P.size()) + " samples, run has " +
                std::to_string(run.P.size()));
  for (const auto* v : {&reference.P, &run.P})
    for (std::size_t i = 0; i < v->size(); ++i)
      if (!std::isfinite((*v)[i])) return fail("P is not finite at sample " + std::to_string(i));
  double d;
  if (defs == Definitions::kAuthorsCode) {
    std::vector<double> ticks(run.P.size());
    for (std::size_t i = 0; i < ticks.size(); ++i) ticks[i] = static_cast<double>(i + 1) * run.interval;
    d = dtwTimeValue(ticks, run.P, ticks, reference.P, band);
  } else {
    d = dtw(run.P, reference.P, band);
  }
  if (!std::isfinite(d)) return fail("DTW distance overflows");
  out.distance = ok(d);
  out.normalized = ok(-logisticSpread(d));  // sigma(-d) - sigma(d)
  return out;
}

MetricValue expectedTimeOut(const PopulationRates& r, double T, Definitions defs) {
  if (defs == Definitions::kAuthorsCode2019) return bad(robustnessUnavailable(defs));
  if (!r.enabled()) return bad("no population dynamics (every rate is 0)");
  if (!(T > 0)) return bad("the run has no ticks (T = " + numberText(T) + ")");
  if (defs == Definitions::kAuthorsCode && r.pureDeath()) return ok(T);  // titerra: pure death -> T
  const double lambda = r.arrival(), mu = r.service();
  if (!(lambda < mu))
    return bad("no steady state: lambda = death + malfunction = " + numberText(lambda) +
               " >= mu = birth + repair = " + numberText(mu) +
               " per tick (the queue of robots out of the swarm "
               "grows without bound)" +
               (defs == Definitions::kPaper && r.pureDeath()
                    ? "; definitions authors_code takes T_bar = T under pure death"
                    : ""));
  const double w = 1.0 / (mu - lambda);
  const double t = defs == Definitions::kPaper ? w - 1.0 / mu : w;
  return std::isfinite(t) ? ok(t) : bad("the expected time out of the swarm overflows");
}

PdRobustness pdRobustness(double P, double P_reference, double T, const PopulationRates& rates,
                          const PopulationRates& reference_rates, Definitions defs) {
  PdRobustness out;
  out.time_out = expectedTimeOut(rates, T, defs);
  const auto fail = [&out](const std::string& why) {
    out.theta = out.normalized = bad(why);
    return out;
  };
  if (!out.time_out.valid) return fail(out.time_out.reason);
  if (!std::isfinite(P) || !std::isfinite(P_reference)) return fail("P is not finite");
  if (defs == Definitions::kPaper) {
    out.weight = (T - out.time_out.value) / T;
  } else {
    const MetricValue w0 = expectedTimeOut(reference_rates, T, defs);
    if (!w0.valid) return fail("the lowest-rate reference: " + w0.reason);
    out.weight = w0.value / out.time_out.value;  // > 0: W > 0 when valid
  }
  const double theta = P - out.weight * P_reference;
  if (!std::isfinite(theta)) return fail("theta overflows");
  out.theta = ok(theta);
  out.normalized = ok(logisticSpread(theta));
  return out;
}

}  // namespace swarm_forage
