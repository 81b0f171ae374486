#include "swarm_forage/core/metrics/swarm_metrics.hpp"

#include <algorithm>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <numeric>
#include <utility>

#include "swarm_forage/core/metrics/dtw.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

namespace {

MetricValue ok(double v) { return {v, true, {}}; }
MetricValue bad(std::string reason) { return {0.0, false, std::move(reason)}; }

/// "" if every value is finite, else "<name> is not finite at sample i".
std::string finiteCheck(const std::vector<double>& v, const std::string& name) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) return name + " is not finite at sample " + std::to_string(i);
  return {};
}

/// Collects per-sample values and reasons; reasons are counted and rendered as
/// "<reason> at every sample" or "<reason> at k of n samples".
class SeriesBuilder {
 public:
  void add(const MetricValue& v) {
    out_.value.push_back(v.valid ? v.value : 0.0);
    out_.sample_valid.push_back(v.valid);
    if (v.valid) return;
    auto it =
        std::find_if(counts_.begin(), counts_.end(), [&](const auto& c) { return c.first == v.reason; });
    if (it == counts_.end())
      counts_.emplace_back(v.reason, 1);
    else
      ++it->second;
  }
  MetricSeries finish(const std::string& if_empty = "no samples") {
    const std::size_t n = out_.value.size();
    out_.valid = n > 0 && counts_.empty();
    if (n == 0) out_.reason = if_empty;
    for (const auto& [reason, k] : counts_) {
      if (!out_.reason.empty()) out_.reason += "; ";
      out_.reason += reason + (k == n ? " at every sample"
                                      : " at " + std::to_string(k) + " of " + std::to_string(n) + " samples");
    }
    return std::move(out_);
  }

 private:
  MetricSeries out_;
  std::vector<std::pair<std::string, std::size_t>> counts_;
};

MetricSeries invalidSeries(const std::string& reason) {
  MetricSeries s;
  s.reason = reason;
  return s;
}

MetricSeries oneValue(double v) {
  SeriesBuilder b;
  b.add(ok(v));
  return b.finish();
}

/// 1 - 1/(1 + e^-theta), without overflow.
double zTerm(double theta) {
  if (theta >= 0) {
    const double e = std::exp(-theta);
    return e / (1.0 + e);
  }
  return 1.0 / (1.0 + std::exp(theta));
}

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

std::string sampleCount(const std::string& who, std::size_t n) {
  return who + " has " + std::to_string(n) + (n == 1 ? " sample" : " samples");
}

}  // namespace

// ---- Definitions -----------------------------------------------------------------------------------

const std::vector<std::string>& definitionsNames() {
  static const std::vector<std::string> names{"paper", "authors_code_2019", "authors_code_2020",
                                              "authors_code"};
  return names;
}

Definitions parseDefinitions(const std::string& name) {
  if (name == "paper") return Definitions::kPaper;
  if (name == "authors_code_2019") return Definitions::kAuthorsCode2019;
  if (name == "authors_code_2020") return Definitions::kAuthorsCode2020;
  if (name == "authors_code") return Definitions::kAuthorsCode;
  std::string valid;
  for (const std::string& n : definitionsNames()) valid += (valid.empty() ? "" : ", ") + n;
  throw ParameterError("definitions must be one of: " + valid + " (got '" + name + "')");
}

const char* definitionsName(Definitions d) {
  switch (d) {
    case Definitions::kPaper:
      return "paper";
    case Definitions::kAuthorsCode2019:
      return "authors_code_2019";
    case Definitions::kAuthorsCode2020:
      return "authors_code_2020";
    case Definitions::kAuthorsCode:
      return "authors_code";
  }
  return "paper";
}

// ---- Aggregation -----------------------------------------------------------------------------------

double studentT95(uint32_t dof) {
  if (dof == 0) return 0.0;
  return boost::math::quantile(boost::math::students_t(static_cast<double>(dof)), 0.975);
}

namespace {
/// aggregateSeries over series held elsewhere: the bootstrap aggregates its draws without copying them.
SeriesStats aggregateSeriesAt(const std::vector<const std::vector<double>*>& series) {
  SeriesStats out;
  out.runs = series.size();
  if (series.empty()) return out;
  std::size_t common = series.front()->size();
  for (const auto* s : series) {
    common = std::min(common, s->size());
    out.longest = std::max(out.longest, s->size());
  }
  out.truncated = common != out.longest;
  const double r = static_cast<double>(series.size());
  const double t = studentT95(static_cast<uint32_t>(series.size() - 1));
  out.mean.reserve(common);
  out.ci95.reserve(common);
  for (std::size_t i = 0; i < common; ++i) {
    double sum = 0;
    for (const auto* s : series) sum += (*s)[i];
    const double m = sum / r;
    double ss = 0;
    for (const auto* s : series) ss += ((*s)[i] - m) * ((*s)[i] - m);
    out.mean.push_back(m);
    out.ci95.push_back(series.size() > 1 ? t * std::sqrt(ss / (r - 1.0)) / std::sqrt(r) : 0.0);
  }
  return out;
}
}  // namespace

SeriesStats aggregateSeries(const std::vector<std::vector<double>>& series) {
  std::vector<const std::vector<double>*> at;
  for (const auto& s : series) at.push_back(&s);
  return aggregateSeriesAt(at);
}

AggregatedRuns aggregateRuns(const std::vector<RunSeries>& runs) {
  std::vector<const RunSeries*> at;
  for (const RunSeries& r : runs) at.push_back(&r);
  return aggregateRuns(at.data(), at.size());
}

AggregatedRuns aggregateRuns(const RunSeries* const* runs, std::size_t count) {
  AggregatedRuns out;
  out.runs = count;
  if (count == 0) {
    out.reason = "no runs";
    return out;
  }
  const RunSeries& first = *runs[0];
  for (std::size_t k = 1; k < count; ++k) {
    if (runs[k]->swarm_size != first.swarm_size) {
      out.reason = "run " + std::to_string(k) + " has " + std::to_string(runs[k]->swarm_size) +
                   " robots, run 0 has " + std::to_string(first.swarm_size);
      return out;
    }
    if (runs[k]->interval != first.interval) {
      out.reason = "run " + std::to_string(k) + " has a sample interval of " +
                   std::to_string(runs[k]->interval) + " ticks, run 0 of " + std::to_string(first.interval);
      return out;
    }
  }
  out.valid = true;
  out.mean.swarm_size = out.ci95.swarm_size = first.swarm_size;
  out.mean.interval = out.ci95.interval = first.interval;
  const std::pair<const char*, std::vector<double> RunSeries::*> fields[] = {
      {"P", &RunSeries::P}, {"p", &RunSeries::p}, {"n_ca", &RunSeries::n_ca}, {"s", &RunSeries::s}};
  for (const auto& [name, field] : fields) {
    std::vector<const std::vector<double>*> series;
    for (std::size_t k = 0; k < count; ++k) series.push_back(&(runs[k]->*field));
    SeriesStats st = aggregateSeriesAt(series);
    out.mean.*field = std::move(st.mean);
    out.ci95.*field = std::move(st.ci95);
    if (!st.truncated) continue;
    out.truncated = true;
    if (!out.note.empty()) out.note += "; ";
    const std::string common = std::to_string((out.mean.*field).size());
    out.note += std::string(name) + ": runs have " + common + " to " + std::to_string(st.longest) +
                " samples, using the common " + common;
  }
  return out;
}

// ---- Scalability -----------------------------------------------------------------------------------

MetricValue karpFlattPhi(double P1, double P2, uint32_t n1, uint32_t n2) {
  if (n1 == 0) return bad("N1 must be >= 1 (got 0)");
  if (n2 <= n1)
    return bad("N2 (" + std::to_string(n2) + ") must be larger than N1 (" + std::to_string(n1) + ")");
  if (!std::isfinite(P1)) return bad("P(N1) is not finite");
  if (!std::isfinite(P2)) return bad("P(N2) is not finite");
  if (P1 == 0.0) return bad("P(N1) is 0");
  return ok(P2 / ((static_cast<double>(n2) / n1) * P1));
}

MetricValue karpFlattE(double phi, uint32_t n) {
  if (n < 2) return bad("e is undefined for N = " + std::to_string(n) + " (0/0 form)");
  if (!std::isfinite(phi)) return bad("phi is not finite");
  if (phi == 0.0) return bad("phi is 0 (P(N2) is 0): e is unbounded");
  const double inv_n = 1.0 / n;
  const double e = (1.0 / phi - inv_n) / (1.0 - inv_n);
  return std::isfinite(e) ? ok(e) : bad("e overflows (phi = " + std::to_string(phi) + ")");
}

Scalability scalability(const RunSeries& run_n1, const RunSeries& run_n2, Definitions defs) {
  Scalability out;
  out.n1 = run_n1.swarm_size;
  out.n2 = run_n2.swarm_size;
  out.n_used = authors2019Rules(defs) || out.n1 == 1 ? out.n2 : out.n1;
  if (authors2019Rules(defs))
    out.note = std::string(definitionsName(defs)) + ": e uses N2 in place of N1";
  else if (out.n1 == 1)
    out.note = "N1 = 1: e uses N2 in place of N1 (the paper's formula is 0/0; authors' implementation)";

  const std::string reason =
      run_n1.P.size() != run_n2.P.size()
          ? sampleCount("N1 run", run_n1.P.size()) + ", " + sampleCount("N2 run", run_n2.P.size())
          : (run_n1.P.empty() ? "no samples" : "");
  if (!reason.empty()) {
    out.phi = out.e = bad(reason);
    out.phi_t = out.e_t = invalidSeries(reason);
    return out;
  }
  SeriesBuilder phi_t, e_t;
  for (std::size_t i = 0; i < run_n1.P.size(); ++i) {
    const MetricValue phi = karpFlattPhi(run_n1.P[i], run_n2.P[i], out.n1, out.n2);
    phi_t.add(phi);
    e_t.add(phi.valid ? karpFlattE(phi.value, out.n_used) : phi);
  }
  out.phi_t = phi_t.finish();
  out.e_t = e_t.finish();
  const std::size_t last = run_n1.P.size() - 1;
  out.phi = karpFlattPhi(run_n1.P[last], run_n2.P[last], out.n1, out.n2);
  out.e = out.phi.valid ? karpFlattE(out.phi.value, out.n_used) : out.phi;
  for (MetricValue* v : {&out.phi, &out.e})
    if (!v->valid) v->reason += " at T";
  return out;
}

// ---- Self-organization -----------------------------------------------------------------------------

MetricSeries tLost(const RunSeries& run) {
  if (run.swarm_size == 0) return invalidSeries("swarm size is 0");
  SeriesBuilder b;
  for (double n_ca : run.n_ca)
    b.add(std::isfinite(n_ca) ? ok(n_ca / run.swarm_size) : bad("n_ca is not finite"));
  return b.finish();
}

MetricSeries pLost(const RunSeries& single, const RunSeries& run) {
  if (single.swarm_size != 1)
    return invalidSeries("single-robot run has " + std::to_string(single.swarm_size) + " robots");
  if (run.swarm_size == 0) return invalidSeries("swarm size is 0");
  const std::size_t n = run.p.size();
  if (run.n_ca.size() != n)
    return invalidSeries(sampleCount("run", n) + " of p, " + std::to_string(run.n_ca.size()) + " of n_ca");
  if (single.p.size() != n || single.n_ca.size() != n)
    return invalidSeries(sampleCount("single-robot run", std::min(single.p.size(), single.n_ca.size())) +
                         ", " + sampleCount("run", n));
  const MetricSeries t1 = tLost(single), tn = tLost(run);
  SeriesBuilder b;
  for (std::size_t i = 0; i < n; ++i) {
    // P_lost(1,t) = p(1,t) t_lost^1(t); P_lost(N,t) = p(N,t) t_lost^N(t) - N P_lost(1,t).
    const double own = run.p[i] * tn.value[i];
    const double lost = run.swarm_size == 1 ? own : own - run.swarm_size * (single.p[i] * t1.value[i]);
    const bool fine = t1.sample_valid[i] && tn.sample_valid[i] && std::isfinite(lost);
    b.add(fine ? ok(lost) : bad("p or n_ca is not finite"));
  }
  return b.finish();
}

SelfOrganization selfOrganization(const RunSeries& single, const RunSeries& prev, const RunSeries& cur,
                                  Definitions defs) {
  SelfOrganization out;
  out.m_prev = prev.swarm_size;
  out.m_cur = cur.swarm_size;
  auto invalid = [&out](const std::string& reason) {
    out.p_lost_prev = out.p_lost_cur = out.theta = invalidSeries(reason);
    out.z_sum = out.z_mean = bad(reason);
    return out;
  };
  if (single.swarm_size != 1)
    return invalid("single-robot run has " + std::to_string(single.swarm_size) + " robots");
  if (out.m_prev < 1 || out.m_cur <= out.m_prev)
    return invalid("m_i (" + std::to_string(out.m_cur) + ") must be larger than m_(i-1) (" +
                   std::to_string(out.m_prev) + ") >= 1");
  if (prev.n_ca.size() != cur.n_ca.size() || single.n_ca.size() != cur.n_ca.size())
    return invalid(sampleCount("single-robot run", single.n_ca.size()) + ", " +
                   sampleCount("run of " + std::to_string(out.m_prev), prev.n_ca.size()) + ", " +
                   sampleCount("run of " + std::to_string(out.m_cur), cur.n_ca.size()));
  if (cur.n_ca.empty()) return invalid("no samples");
  const double ratio = static_cast<double>(out.m_cur) / out.m_prev;

  if (authors2019Rules(defs)) {
    for (const RunSeries* r : {&single, &prev, &cur})
      if (const std::string f = finiteCheck(r->n_ca, "n_ca"); !f.empty()) return invalid(f);
    const double n_ca_1 = mean(single.n_ca);
    auto pl = [&](const RunSeries& r) { return (mean(r.n_ca) - r.swarm_size * n_ca_1) / r.swarm_size; };
    const double pl_prev = pl(prev), pl_cur = pl(cur), theta = pl_cur - ratio * pl_prev;
    out.p_lost_prev = oneValue(pl_prev);
    out.p_lost_cur = oneValue(pl_cur);
    out.theta = oneValue(theta);
    const double z = 1.0 - std::exp(theta);
    out.z_sum = out.z_mean =
        std::isfinite(z) ? ok(z) : bad("theta = " + std::to_string(theta) + ": 1 - e^theta overflows");
    return out;
  }

  const MetricSeries p_lost_prev = pLost(single, prev), p_lost_cur = pLost(single, cur);
  for (const MetricSeries* pl : {&p_lost_prev, &p_lost_cur})
    if (!pl->valid) return invalid(pl->reason);
  out.p_lost_prev = p_lost_prev;
  out.p_lost_cur = p_lost_cur;
  SeriesBuilder theta;
  double z = 0;
  for (std::size_t i = 0; i < p_lost_cur.value.size(); ++i) {
    const double th = p_lost_cur.value[i] - ratio * p_lost_prev.value[i];
    theta.add(ok(th));
    z += zTerm(th);
  }
  out.theta = theta.finish();
  out.z_sum = ok(z);
  out.z_mean = ok(z / static_cast<double>(p_lost_cur.value.size()));
  return out;
}

// ---- Reactivity and adaptability -------------------------------------------------------------------

std::vector<double> minMaxMap(const std::vector<double>& x, double a, double b) {
  if (x.empty()) return {};
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  const double min = *lo, range = *hi - *lo;
  std::vector<double> out;
  out.reserve(x.size());
  for (double v : x) out.push_back(range > 0 ? (b - a) * (v - min) / range + a : a + (b - a) / 2);
  return out;
}

std::vector<double> reactivityIdeal(const std::vector<double>& s, const std::vector<double>& p_ideal) {
  if (s.empty() || p_ideal.empty()) return {};
  const auto [lo, hi] = std::minmax_element(p_ideal.begin(), p_ideal.end());
  return minMaxMap(s, *lo, *hi);
}

std::vector<double> adaptabilityIdeal(const std::vector<double>& s, const std::vector<double>& p_ideal) {
  std::vector<double> out;
  for (std::size_t i = 0; i < std::min(s.size(), p_ideal.size()); ++i)
    out.push_back(s[i] > 1.0 ? p_ideal[i] * s[i] : p_ideal[i]);
  return out;
}

namespace {

std::string flexibilityCheck(const RunSeries& ideal, const RunSeries& run) {
  if (ideal.p.empty()) return "reference run has no samples";
  if (run.p.empty()) return "run has no samples";
  if (ideal.swarm_size != run.swarm_size)
    return "reference run has " + std::to_string(ideal.swarm_size) + " robots, run has " +
           std::to_string(run.swarm_size);
  if (ideal.interval != run.interval)
    return "reference run has a sample interval of " + std::to_string(ideal.interval) + " ticks, run of " +
           std::to_string(run.interval);
  if (ideal.p.size() != run.p.size())
    return sampleCount("reference run", ideal.p.size()) + ", run has " + std::to_string(run.p.size());
  if (run.s.size() != run.p.size())
    return sampleCount("run", run.p.size()) + " of p, " + std::to_string(run.s.size()) + " of s";
  const std::pair<const std::vector<double>*, const char*> values[] = {
      {&ideal.p, "reference p"}, {&run.p, "p"}, {&run.s, "s"}};
  for (const auto& [v, name] : values)
    if (std::string f = finiteCheck(*v, name); !f.empty()) return f;
  return {};
}

Flexibility flexibility(const RunSeries& ideal, const RunSeries& run, Definitions defs,
                        std::optional<std::size_t> band, bool reactive) {
  Flexibility out;
  if (const std::string why = flexibilityCheck(ideal, run); !why.empty()) {
    out.distance = bad(why);
    return out;
  }
  std::vector<double> curve = reactive ? reactivityIdeal(run.s, ideal.p) : adaptabilityIdeal(run.s, ideal.p);
  if (const std::string f = finiteCheck(curve, reactive ? "P_R*" : "P_A*"); !f.empty()) {
    out.distance = bad(f);
    return out;
  }
  double d;
  if (authors2019Rules(defs)) {
    std::vector<double> ticks(curve.size());
    for (std::size_t i = 0; i < ticks.size(); ++i) ticks[i] = static_cast<double>(i + 1) * run.interval;
    d = dtwTimeValue(ticks, curve, ticks, run.p, band);
  } else {
    d = dtw(curve, run.p, band);
  }
  out.distance = std::isfinite(d) ? ok(d) : bad("DTW distance overflows");
  if (out.distance.valid) out.ideal = std::move(curve);
  return out;
}

}  // namespace

Flexibility reactivity(const RunSeries& ideal, const RunSeries& run, Definitions defs,
                       std::optional<std::size_t> band) {
  return flexibility(ideal, run, defs, band, true);
}

Flexibility adaptability(const RunSeries& ideal, const RunSeries& run, Definitions defs,
                         std::optional<std::size_t> band) {
  return flexibility(ideal, run, defs, band, false);
}

}  // namespace swarm_forage
