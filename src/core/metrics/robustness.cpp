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

std::vector<double> cumulativeAverage(const RunSeries& r) {
  std::vector<double> out(r.P.size());
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = r.P[k] / (static_cast<double>(k + 1) * static_cast<double>(r.interval));
  return out;
}

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
  if (run.interval == 0) return fail("the sample interval is 0");
  double d;
  if (defs == Definitions::kPaper) {
    d = dtw(run.P, reference.P, band);
  } else {
    // Their curve (cum_avg_transported) against x: the row of their collated table (titerra, per simulation)
    // or the tick of its "clock" column (sierra's averaged tables in 2020).
    std::vector<double> x(run.P.size());
    for (std::size_t k = 0; k < x.size(); ++k)
      x[k] = defs == Definitions::kAuthorsCode ? static_cast<double>(k)
                                               : static_cast<double>(k + 1) * run.interval;
    d = dtwTimeValue(x, cumulativeAverage(run), x, cumulativeAverage(reference), band);
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
  if (defs == Definitions::kAuthorsCode2020) {
    // sierra's calc_tasked_swarm_time gives T_S, the time in the swarm, and the weight T_S / T: 0 under pure
    // death; T when 1/(mu - lambda) or 1/mu divides by zero; T - T_bar otherwise, whatever the sign of
    // mu - lambda. T_bar = T - T_S.
    if (r.pureDeath()) return ok(T);
    if (mu - lambda == 0 || mu == 0) return ok(0.0);
    const double t_bar = 1.0 / (mu - lambda) - 1.0 / mu;
    return std::isfinite(t_bar) ? ok(t_bar) : bad("the expected time out of the swarm overflows");
  }
  if (!(lambda < mu))
    return bad("no steady state: lambda = death + malfunction = " + numberText(lambda) +
               " >= mu = birth + repair = " + numberText(mu) +
               " per tick (the queue of robots out of the swarm "
               "grows without bound)" +
               (defs == Definitions::kPaper && r.pureDeath()
                    ? "; definitions authors_code_2020 and authors_code take T_bar = T under pure death"
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
  double theta;
  if (defs != Definitions::kAuthorsCode) {
    out.weight = (T - out.time_out.value) / T;
    theta = P - out.weight * P_reference;
  } else {
    const MetricValue w0 = expectedTimeOut(reference_rates, T, defs);
    if (!w0.valid) return fail("the lowest-rate reference: " + w0.reason);
    out.weight = w0.value / out.time_out.value;      // > 0: W > 0 when valid
    theta = P / T - out.weight * (P_reference / T);  // the last row of their curve, cum_avg_transported
  }
  if (!std::isfinite(theta)) return fail("theta overflows");
  out.theta = ok(theta);
  out.normalized = ok(logisticSpread(theta));
  return out;
}

QueueCheck queueCheck(const PopulationRates& r, const std::optional<OutOfSwarm>& measured) {
  QueueCheck q;
  const double lambda = r.arrival(), mu = r.service();
  if (lambda < mu) {
    q.time_out_queue = 1.0 / (mu - lambda);
    q.out_queue = lambda / (mu - lambda);
  }
  if (measured) {
    q.time_out_measured = measured->meanTimeOut();
    q.out_measured = measured->meanOut();
    q.outages = measured->returns;
  }
  const auto compare = [&q](const std::optional<double>& predicted, const std::optional<double>& seen) {
    if (!predicted || !seen) return;
    const bool off = std::abs(*seen - *predicted) > kQueueTolerance * *predicted;
    q.differs = q.differs.value_or(false) || off;
  };
  compare(q.time_out_queue, q.time_out_measured);
  compare(q.out_queue, q.out_measured);
  return q;
}

}  // namespace swarm_forage
