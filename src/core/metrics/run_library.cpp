#include "swarm_forage/core/metrics/run_library.hpp"

#include <algorithm>
#include <cstdio>
#include <set>
#include <string>
#include <tuple>

#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

std::string numberText(double v, bool exact) {
  char buf[40];
  std::snprintf(buf, sizeof buf, exact ? "%.17g" : "%g", v);
  return buf;
}

std::string csvQuoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

namespace {
/// One group for every way of writing the same condition.
RunKey normalized(RunKey k) {
  k.environment = k.environment.normalized();
  return k;
}

/// A lone robot that never loses time to interference: P_lost(1, t) = 0 where no N = 1 run exists.
RunSeries withoutInterference(const RunSeries& like) {
  RunSeries one;
  one.swarm_size = 1;
  one.interval = like.interval;
  one.P.assign(like.P.size(), 0.0);
  one.p.assign(like.p.size(), 0.0);
  one.n_ca.assign(like.n_ca.size(), 0.0);
  one.s.assign(like.s.size(), 1.0);
  return one;
}

void setStatus(Evaluated& e, const MetricValue& v, uint32_t reference_size) {
  e.valid = v.valid;
  e.status = v.valid ? "ok" : v.reason;
  e.reference_size = reference_size;
}

void setMissing(Evaluated& e, const std::string& why) {
  e.valid = false;
  e.status = why;
}
}  // namespace

bool RunSetup::operator<(const RunSetup& o) const {
  return std::tie(arena_width, arena_height, cube_size, ramp_length, n_blocks, ticks, ticks_per_second, mode,
                  world_constants, controller_constants, interval) <
         std::tie(o.arena_width, o.arena_height, o.cube_size, o.ramp_length, o.n_blocks, o.ticks,
                  o.ticks_per_second, o.mode, o.world_constants, o.controller_constants, o.interval);
}

bool RunKey::operator<(const RunKey& o) const {
  return std::tie(controller, arena, environment, swarm_size, setup) <
         std::tie(o.controller, o.arena, o.environment, o.swarm_size, o.setup);
}

std::string RunKey::label() const {
  return controller + " " + arena + " N=" + std::to_string(swarm_size) + " " + environment.label();
}

namespace {
/// Only what differs from the paper's condition, so that every identity from before targets and series stays.
std::string targetAndSeries(const Condition& e) {
  return (e.target == "carry_speed" ? "" : " target=" + e.target) +
         (e.waveform == "series" ? " series=" + e.series_digest : "");
}

std::string describeWithoutInterval(const RunKey& k) {
  const Condition e = k.environment.normalized();
  const RunSetup& s = k.setup;
  return "controller=" + k.controller + " arena=" + k.arena + " arena_x=" + canonicalNumber(s.arena_width) +
         " arena_y=" + canonicalNumber(s.arena_height) + " blocks=" + std::to_string(s.n_blocks) +
         " cube_size=" + canonicalNumber(s.cube_size) + " ramp_length=" + canonicalNumber(s.ramp_length) +
         " N=" + std::to_string(k.swarm_size) + " ticks=" + std::to_string(s.ticks) +
         " ticks_per_second=" + canonicalNumber(s.ticks_per_second) + " mode=" + s.mode +
         " waveform=" + e.waveform + " beta=" + canonicalNumber(e.beta) +
         " alpha=" + canonicalNumber(e.alpha) + " frequency=" + canonicalNumber(e.frequency) +
         " phase=" + canonicalNumber(e.phase) + " offset=" + canonicalNumber(e.offset) + targetAndSeries(e) +
         " world: " + s.world_constants + " controller: " + s.controller_constants;
}
}  // namespace

std::string RunKey::describe() const {
  return describeWithoutInterval(*this) + " sample_interval=" + std::to_string(setup.interval);
}

std::string RunKey::identity() const {
  uint32_t h = 2166136261u;  // FNV-1a: stable across builds and platforms, unlike std::hash
  for (const unsigned char c : describeWithoutInterval(*this)) h = (h ^ c) * 16777619u;
  char buf[9];
  std::snprintf(buf, sizeof buf, "%08x", h);
  return buf;
}

RunSeriesBuilder::RunSeriesBuilder(uint32_t interval, uint32_t swarm_size) : accumulator_(interval) {
  series_.interval = interval;
  series_.swarm_size = swarm_size;
}

std::optional<IntervalSample> RunSeriesBuilder::add(uint64_t tick, uint32_t delivered, uint64_t cumulative,
                                                    uint32_t in_avoidance, bool last, double throttle) {
  auto sample = accumulator_.add(tick, delivered, cumulative, in_avoidance, last, throttle);
  if (!sample) return sample;
  series_.P.push_back(static_cast<double>(sample->cumulative));
  series_.p.push_back(sample->delivered);
  series_.n_ca.push_back(sample->mean_in_avoidance);
  series_.s.push_back(sample->speed);
  finished_ = sample->final;
  return sample;
}

RunSeries firstSamples(const RunSeries& r, std::size_t samples) {
  RunSeries out = r;
  for (std::vector<double>* v : {&out.P, &out.p, &out.n_ca, &out.s})
    if (v->size() > samples) v->resize(samples);
  return out;
}

namespace {
bool isLive(const RunRecord& r) { return r.source.rfind("live run", 0) == 0; }
bool sameSeries(const RunSeries& a, const RunSeries& b) {
  return a.swarm_size == b.swarm_size && a.interval == b.interval && a.P == b.P && a.p == b.p &&
         a.n_ca == b.n_ca && a.s == b.s;
}
}  // namespace

AddResult RunLibrary::add(const RunRecord& run) {
  RunRecord r = run;
  r.key = normalized(r.key);
  if (runs_.use_count() > 1) runs_ = std::make_shared<Runs>(*runs_);  // a copy shares them
  auto& seeds = (*runs_)[r.key];
  AddResult result;
  // A group's seeds are runs of one model: a record of another model version is never averaged in.
  for (const auto& [seed, had] : seeds)
    if (r.model_version && had.model_version && had.model_version != r.model_version) {
      result.added = false;
      result.problem = r.source + ": made by model version " + std::to_string(r.model_version) + ", but " +
                       had.source + " of the same runs (" + r.key.label() + " #" + r.key.identity() +
                       ") by model version " + std::to_string(had.model_version) +
                       ": records of different model versions are never grouped (remake the older)";
      return result;
    }
  if (const auto it = seeds.find(r.seed); it != seeds.end()) {
    const RunRecord& had = it->second;
    const bool reread = had.source == r.source;
    const bool own_recording = isLive(had) != isLive(r) && sameSeries(had.series, r.series);
    if (!reread && !own_recording) {
      result.added = false;
      result.problem = r.source + ": the same run (" + r.key.label() + " #" + r.key.identity() + ", seed " +
                       std::to_string(r.seed) + ") as " + had.source + ", which is the one used" +
                       (sameSeries(had.series, r.series) ? " (identical series)" : " (their series differ)");
      return result;
    }
    if (own_recording && !isLive(had)) {
      result.added = false;  // keep the bag; the live copy is the same run
      return result;
    }
  }
  seeds[r.seed] = r;
  std::vector<const RunSeries*> series;
  for (const auto& [seed, rec] : seeds) series.push_back(&rec.series);
  groups_[r.key] = aggregateRuns(series.data(), series.size());
  return result;
}

RunLibrary RunLibrary::resampled(uint64_t seed, uint32_t draw) const {
  RunLibrary out;
  out.runs_ = runs_;  // shared, not copied: a draw changes only the groups
  for (const auto& [key, seeds] : *runs_) {
    std::vector<const RunSeries*> all;
    for (const auto& [s, rec] : seeds) all.push_back(&rec.series);
    CounterRng rng(seed, RngStream::kBootstrap, std::stoul(key.identity(), nullptr, 16), draw);
    std::vector<const RunSeries*> drawn;
    for (std::size_t i = 0; i < all.size(); ++i)
      drawn.push_back(all[std::min(all.size() - 1, static_cast<std::size_t>(rng.uniform() * all.size()))]);
    out.groups_.emplace_hint(out.groups_.end(), key, aggregateRuns(drawn.data(), drawn.size()));
  }
  return out;
}

std::size_t RunLibrary::size() const {
  std::size_t n = 0;
  for (const auto& [key, seeds] : *runs_) n += seeds.size();
  return n;
}

std::vector<const RunRecord*> RunLibrary::runs(const RunKey& key) const {
  std::vector<const RunRecord*> out;
  const auto it = runs_->find(normalized(key));
  if (it == runs_->end()) return out;
  for (const auto& [seed, rec] : it->second) out.push_back(&rec);
  return out;
}

Reference RunLibrary::lookup(const RunKey& wanted, const std::string& description) const {
  Reference ref;
  const auto it = groups_.find(wanted);
  if (it != groups_.end() && it->second.valid) {
    ref.runs = &it->second;
    return ref;
  }
  ref.missing = "no " + description + " in the library";
  if (it != groups_.end()) {
    ref.missing = "the " + description + " cannot be used: " + it->second.reason;
    return ref;
  }
  // Say what is there instead: the same size under another controller, arena or environment.
  std::set<std::string> others;
  for (const auto& [key, group] : groups_)
    if (key.swarm_size == wanted.swarm_size) others.insert(key.label());
  if (!others.empty()) {
    ref.missing += " (at N=" + std::to_string(wanted.swarm_size) + " it has only:";
    for (const std::string& o : others) ref.missing += " [" + o + "]";
    ref.missing += ")";
  }
  return ref;
}

Reference RunLibrary::smaller(const RunKey& key) const {
  const RunKey k = normalized(key);
  const RunKey* best = nullptr;
  for (const auto& [other, group] : groups_)
    if (other.controller == k.controller && other.arena == k.arena && other.environment == k.environment &&
        other.setup == k.setup && other.swarm_size < k.swarm_size &&
        (!best || other.swarm_size > best->swarm_size))
      best = &other;
  const std::string what = "run of " + k.controller + " in " + k.arena + " under " + k.environment.label() +
                           " at N < " + std::to_string(k.swarm_size);
  if (best) return lookup(*best, what);
  Reference ref;
  ref.missing = "no " + what + " in the library";
  return ref;
}

Reference RunLibrary::single(const RunKey& key) const {
  RunKey k = normalized(key);
  k.swarm_size = 1;
  return lookup(
      k, "run of " + k.controller + " in " + k.arena + " under " + k.environment.label() + " at N = 1");
}

Reference RunLibrary::ideal(const RunKey& key) const {
  RunKey k = normalized(key);
  k.environment = Condition{};
  return lookup(k, "ideal run (V = 0) of " + k.controller + " in " + k.arena +
                       " at N = " + std::to_string(k.swarm_size));
}

Reference RunLibrary::find(const RunKey& key, const std::string& description) const {
  return lookup(normalized(key), description);
}

RunEvaluation evaluateRun(const RunLibrary& library, const RunKey& key, const RunSeries& series, bool final,
                          Definitions defs, std::optional<std::size_t> band) {
  RunEvaluation ev;
  const RunKey k = normalized(key);
  const std::size_t samples = series.P.size();
  const auto reference = [&](const Reference& r) {
    return final ? r.runs->mean : firstSamples(r.runs->mean, samples);
  };

  if (k.swarm_size <= 1) {
    setMissing(ev.scalability_status, "N = 1: there is no smaller swarm to compare with");
    setMissing(ev.self_organization_status, "N = 1: Z compares a swarm with smaller ones");
  } else if (const Reference prev = library.smaller(k); !prev.runs) {
    setMissing(ev.scalability_status, prev.missing);
    setMissing(ev.self_organization_status, prev.missing);
  } else {
    const RunSeries prev_series = reference(prev);
    ev.scalability = scalability(prev_series, series, defs);
    setStatus(ev.scalability_status, ev.scalability.e, prev_series.swarm_size);
    if (prev_series.swarm_size == 1) {
      ev.self_organization = selfOrganization(prev_series, prev_series, series, defs);
      setStatus(ev.self_organization_status, ev.self_organization.z_sum, 1);
    } else {
      const Reference one = library.single(k);
      ev.self_organization = selfOrganization(one.runs ? reference(one) : withoutInterference(series),
                                              prev_series, series, defs);
      setStatus(ev.self_organization_status, ev.self_organization.z_sum, prev_series.swarm_size);
      if (!one.runs && ev.self_organization_status.valid)
        ev.self_organization_status.status =
            "ok, but " + one.missing +
            (defs == Definitions::kPaper ? ": not needed, P_lost(1, t) cancels from theta_Z when m_(i-1) > 1"
                                         : ": P_lost(1) taken as 0 (an approximation)");
    }
  }

  if (k.environment.ideal()) {
    const std::string why =
        "the run is ideal (V = 0); R and A compare a run under a varying condition "
        "with the ideal run";
    setMissing(ev.reactivity_status, why);
    setMissing(ev.adaptability_status, why);
  } else if (const Reference ideal = library.ideal(k); !ideal.runs) {
    setMissing(ev.reactivity_status, ideal.missing);
    setMissing(ev.adaptability_status, ideal.missing);
  } else {
    const RunSeries ideal_series = reference(ideal);
    ev.reactivity = reactivity(ideal_series, series, defs, band);
    ev.adaptability = adaptability(ideal_series, series, defs, band);
    setStatus(ev.reactivity_status, ev.reactivity.distance, k.swarm_size);
    setStatus(ev.adaptability_status, ev.adaptability.distance, k.swarm_size);
  }
  return ev;
}

}  // namespace swarm_forage
