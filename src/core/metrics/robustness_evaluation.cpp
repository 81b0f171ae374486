#include "swarm_forage/core/metrics/robustness_evaluation.hpp"

#include <tuple>
#include <vector>

namespace swarm_forage {

namespace {

RunKey withWorld(RunKey k, const std::string& world_constants) {
  k.setup.world_constants = world_constants;
  return k;
}

double lastP(const RunSeries& s) { return s.P.empty() ? 0.0 : s.P.back(); }

/// A run and the reference run of the same seed, the reference cut to the run's samples while it is going.
struct Pair {
  RunSeries run, reference;
};

/// authors_code compares simulation i with simulation i of the reference: here, runs of equal seed. One pair
/// for a single run (`seed`), one per run of the group otherwise; `unpaired` lists the seeds without a
/// partner.
std::vector<Pair> pairBySeed(const RunLibrary& library, const RunKey& key, const RunSeries& series,
                             std::optional<uint32_t> seed, const RunKey& reference, bool final,
                             std::string& unpaired) {
  std::vector<std::pair<uint32_t, const RunSeries*>> runs;
  if (seed) {
    runs.emplace_back(*seed, &series);
  } else {
    for (const RunRecord* r : library.runs(key)) runs.emplace_back(r->seed, &r->series);
  }
  const std::vector<const RunRecord*> refs = library.runs(reference);
  std::vector<Pair> out;
  for (const auto& [s, run] : runs) {
    const RunRecord* match = nullptr;
    for (const RunRecord* r : refs)
      if (r->seed == s) match = r;
    if (!match) {
      unpaired += (unpaired.empty() ? "" : ", ") + std::to_string(s);
      continue;
    }
    out.push_back({*run, final ? match->series : firstSamples(match->series, run->P.size())});
  }
  return out;
}

/// The status of a measure averaged over seed pairs.
void pairedStatus(Evaluated& st, const MetricValue& first_invalid, std::size_t used, std::size_t runs,
                  const std::string& unpaired) {
  st.reference_size = static_cast<uint32_t>(used);
  if (used == 0) {
    st.valid = false;
    st.status =
        "no reference run has the seed of the run (authors_code pairs runs by seed; unpaired seeds: " +
        unpaired + ")";
    return;
  }
  st.valid = first_invalid.valid;
  st.status = first_invalid.valid ? "ok" : first_invalid.reason;
  if (st.valid && used < runs)
    st.status = "ok, but seeds " + unpaired + " have no reference run of the same seed (" +
                std::to_string(used) + " of " + std::to_string(runs) + " runs used)";
}

/// The authors' exp0 of `key`'s batch: same identity but for the four rates, the same rates non-zero, the
/// same max_size, the smallest sum of rates (then the smallest death, birth, malfunction, repair).
const RunKey* lowestRate(const RunLibrary& library, const RunKey& key, const RobustnessWords& words) {
  const PopulationRates& r = words.population;
  const auto pattern = [](const PopulationRates& p) {
    return std::make_tuple(p.death > 0, p.birth > 0, p.malfunction > 0, p.repair > 0, p.max_size);
  };
  const auto order = [](const PopulationRates& p) {
    return std::make_tuple(p.death + p.birth + p.malfunction + p.repair, p.death, p.birth, p.malfunction,
                           p.repair);
  };
  const RunKey* best = nullptr;
  PopulationRates best_rates;
  for (const auto& [other, group] : library.groups()) {
    if (!group.valid) continue;
    RunKey same = withWorld(key, other.setup.world_constants);
    same.environment = same.environment.normalized();  // as the library's keys
    if (other < same || same < other) continue;        // differs in more than its world constants
    const RobustnessWords o = robustnessWords(other.setup.world_constants);
    if (!o.problem.empty() || o.without_population != words.without_population || !o.population.enabled() ||
        pattern(o.population) != pattern(r))
      continue;
    if (!best || order(o.population) < order(best_rates)) {
      best = &other;
      best_rates = o.population;
    }
  }
  return best;
}

void evaluateSaa(RobustnessEvaluation& ev, const RunLibrary& library, const RunKey& key,
                 const RunSeries& series, std::optional<uint32_t> seed, bool final, Definitions defs,
                 std::optional<std::size_t> band) {
  const RunKey reference = withWorld(key, ev.words.without_noise);
  ev.saa_reference = reference.identity();
  const Reference ref = library.find(
      reference, "noise-free run #" + ev.saa_reference + " (the same identity without noise/ words)");
  if (!ref.runs) {
    ev.saa_status = {false, ref.missing, 0};
    return;
  }
  if (defs != Definitions::kAuthorsCode) {
    const RunSeries reference_series = final ? ref.runs->mean : firstSamples(ref.runs->mean, series.P.size());
    ev.saa_P_reference = lastP(reference_series);
    ev.saa = saaRobustness(reference_series, series, defs, band);
    ev.saa_status = {ev.saa.distance.valid, ev.saa.distance.valid ? "ok" : ev.saa.distance.reason,
                     static_cast<uint32_t>(ref.runs->runs)};
    return;
  }
  std::string unpaired;
  const std::vector<Pair> pairs = pairBySeed(library, key, series, seed, reference, final, unpaired);
  MetricValue first_invalid{0, true, {}};
  double d = 0, normalized = 0;
  for (const Pair& p : pairs) {
    const SaaRobustness one = saaRobustness(p.reference, p.run, defs, band);
    if (!one.distance.valid && first_invalid.valid) first_invalid = one.distance;
    d += one.distance.value / static_cast<double>(pairs.size());
    ev.saa_P_reference += lastP(p.reference) / static_cast<double>(pairs.size());
    normalized += one.normalized.value / static_cast<double>(pairs.size());
  }
  pairedStatus(ev.saa_status, first_invalid, pairs.size(), seed ? 1 : library.runs(key).size(), unpaired);
  ev.saa.distance =
      ev.saa_status.valid ? MetricValue{d, true, {}} : MetricValue{0, false, ev.saa_status.status};
  ev.saa.normalized = ev.saa.distance.valid ? MetricValue{normalized, true, {}} : ev.saa.distance;
}

void evaluatePd(RobustnessEvaluation& ev, const RunLibrary& library, const RunKey& key,
                const RunSeries& series, std::optional<uint32_t> seed, bool final, Definitions defs) {
  const PopulationRates& rates = ev.words.population;
  if (defs != Definitions::kAuthorsCode) {
    const RunKey reference = withWorld(key, ev.words.without_population);
    ev.pd_reference = reference.identity();
    const std::string what = "run without population dynamics #" + ev.pd_reference;
    const Reference ref = library.find(reference, what + " (the same identity without population/ words)");
    if (!ref.runs) {
      ev.pd.time_out = expectedTimeOut(rates, ev.T, defs);
      ev.pd_status = {false, ref.missing, 0};
      return;
    }
    ev.P_reference = lastP(final ? ref.runs->mean : firstSamples(ref.runs->mean, series.P.size()));
    ev.pd = pdRobustness(ev.P, ev.P_reference, ev.T, rates, PopulationRates{}, defs);
    ev.pd_status = {ev.pd.theta.valid, ev.pd.theta.valid ? "ok" : ev.pd.theta.reason,
                    static_cast<uint32_t>(ref.runs->runs)};
    return;
  }
  ev.pd.time_out = expectedTimeOut(rates, ev.T, defs);
  const RunKey* lowest = lowestRate(library, key, ev.words);
  if (!lowest) {
    ev.pd_status = {false,
                    "no run of this batch (the same identity but for the rates, with the same rates "
                    "non-zero) in the library",
                    0};
    return;
  }
  ev.pd_reference = lowest->identity();
  const PopulationRates reference_rates = robustnessWords(lowest->setup.world_constants).population;
  std::string unpaired;
  const std::vector<Pair> pairs = pairBySeed(library, key, series, seed, *lowest, final, unpaired);
  MetricValue first_invalid{0, true, {}};
  double theta = 0, normalized = 0;
  for (const Pair& p : pairs) {
    const PdRobustness one =
        pdRobustness(lastP(p.run), lastP(p.reference), ev.T, rates, reference_rates, defs);
    if (!one.theta.valid && first_invalid.valid) first_invalid = one.theta;
    ev.pd.weight = one.weight;
    ev.P_reference += lastP(p.reference) / static_cast<double>(pairs.size());
    theta += one.theta.value / static_cast<double>(pairs.size());
    normalized += one.normalized.value / static_cast<double>(pairs.size());
  }
  pairedStatus(ev.pd_status, first_invalid, pairs.size(), seed ? 1 : library.runs(key).size(), unpaired);
  ev.pd.theta =
      ev.pd_status.valid ? MetricValue{theta, true, {}} : MetricValue{0, false, ev.pd_status.status};
  ev.pd.normalized = ev.pd.theta.valid ? MetricValue{normalized, true, {}} : ev.pd.theta;
}

}  // namespace

RobustnessEvaluation evaluateRobustness(const RunLibrary& library, const RunKey& key, const RunSeries& series,
                                        std::optional<uint32_t> seed, bool final, Definitions defs,
                                        std::optional<std::size_t> band) {
  RobustnessEvaluation ev;
  ev.words = robustnessWords(key.setup.world_constants);
  ev.saa_applies = !ev.words.noise.empty();
  ev.pd_applies = ev.words.population.enabled();
  ev.T = final ? static_cast<double>(key.setup.ticks)
               : static_cast<double>(series.P.size()) * static_cast<double>(series.interval);
  ev.P = lastP(series);
  const auto none = [&](Evaluated& st, bool applies, const char* what) {
    if (!ev.words.problem.empty())
      st = {false, ev.words.problem, 0};
    else if (!applies)
      st = {false, std::string("the run has no ") + what, 0};
    else if (defs == Definitions::kAuthorsCode2019)
      st = {false, robustnessUnavailable(defs), 0};
    else
      return false;
    return true;
  };
  if (!none(ev.saa_status, ev.saa_applies, "sensor or actuator noise"))
    evaluateSaa(ev, library, key, series, seed, final, defs, band);
  if (!none(ev.pd_status, ev.pd_applies, "population dynamics"))
    evaluatePd(ev, library, key, series, seed, final, defs);
  if (ev.pd_applies && ev.words.problem.empty()) {
    // Measured over the library's records of the run (its seed) or of the group: final totals only.
    std::optional<OutOfSwarm> measured;
    if (final)
      for (const RunRecord* r : library.runs(key))
        if ((!seed || r->seed == *seed) && r->out_of_swarm) {
          if (!measured) measured.emplace();
          measured->add(*r->out_of_swarm);
        }
    ev.queue = queueCheck(ev.words.population, measured);
  }
  return ev;
}

}  // namespace swarm_forage
