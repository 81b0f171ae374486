// The CSV tables of metrics/compute: every group of the library evaluated like a finished live run.
#include <sstream>

#include "swarm_forage/core/metrics/robustness_evaluation.hpp"
#include "swarm_forage/core/metrics/run_library.hpp"

namespace swarm_forage {

namespace {
std::string num(double v) { return numberText(v, /*exact=*/true); }
std::string num(const std::optional<double>& v) { return v ? num(*v) : std::string(); }

/// The columns every table starts with (beta as given, not to 17 digits).
std::string describe(const RunKey& k) {
  return k.controller + "," + k.arena + "," + k.environment.waveform + "," + numberText(k.environment.beta) +
         "," + csvQuoted(k.environment.label());
}

/// The columns every row ends with: the sample interval the series were cut at, the group's identity.
std::string setup(const RunKey& k) {
  return "," + std::to_string(k.setup.interval) + "," + k.identity() + "\n";
}

double at(const std::vector<double>& v, std::size_t k) { return k < v.size() ? v[k] : 0.0; }

void note(MetricTables& t, const RunKey& k, const char* metric, const Evaluated& e) {
  if (!e.valid) t.problems.push_back(k.label() + ": " + metric + ": " + e.status);
}

/// robustness.csv's header; robustness_runs.csv has `seed` in place of `runs` (docs/robustness-measures.md).
std::string robustnessHead(const char* count) {
  return std::string("controller,arena,waveform,beta,environment,N,") + count +
         ",measure,noise,noise_level,death,birth,malfunction,repair,max_size,T,T_bar,"
         "time_out_queue,time_out_measured,out_queue,out_measured,outages,queue_differs,"
         "P,P_reference,value,normalized,valid,status,reference,reference_runs,sample_interval,identity\n";
}

/// The rows of one run or group (`count`: its number of runs, or its seed): one per measure that applies.
void robustnessRows(std::ostream& out, const RunKey& key, const std::string& count,
                    const RobustnessEvaluation& ev) {
  const PopulationRates& r = ev.words.population;
  const std::string common = describe(key) + ',' + std::to_string(key.swarm_size) + ',' + count + ',';
  const std::string words = csvQuoted(ev.words.noise) + ',' + num(ev.words.noise_level) + ',' + num(r.death) +
                            ',' + num(r.birth) + ',' + num(r.malfunction) + ',' + num(r.repair) + ',' +
                            std::to_string(r.max_size) + ',' + num(ev.T) + ',';
  // The queue's prediction and what the records show: PD rows only (empty fields where there is none).
  const QueueCheck& q = ev.queue;
  const std::string queue = num(q.time_out_queue) + ',' + num(q.time_out_measured) + ',' + num(q.out_queue) +
                            ',' + num(q.out_measured) + ',' +
                            (q.out_measured ? std::to_string(q.outages) : "") + ',' +
                            (q.differs ? (*q.differs ? "1" : "0") : "");
  const auto row = [&](const char* measure, double t_bar, const std::string& queue_fields, double p_reference,
                       const MetricValue& value, const MetricValue& normalized, const Evaluated& st,
                       const std::string& reference) {
    out << common << measure << ',' << words << num(t_bar) << ',' << queue_fields << ',' << num(ev.P) << ','
        << num(p_reference) << ',' << num(value.value) << ',' << num(normalized.value) << ','
        << (st.valid ? 1 : 0) << ',' << csvQuoted(st.status) << ',' << reference << ',' << st.reference_size
        << setup(key);
  };
  if (ev.saa_applies)
    row("saa", 0.0, ",,,,,", ev.saa_P_reference, ev.saa.distance, ev.saa.normalized, ev.saa_status,
        ev.saa_reference);
  if (ev.pd_applies)
    row("pd", ev.pd.time_out.value, queue, ev.P_reference, ev.pd.theta, ev.pd.normalized, ev.pd_status,
        ev.pd_reference);
}
}  // namespace

MetricTables metricTables(const RunLibrary& library, Definitions defs, std::optional<std::size_t> band) {
  MetricTables t;
  std::ostringstream sc, so, fx;
  const char* head = "controller,arena,waveform,beta,environment,";
  const char* tail = ",sample_interval,identity\n";
  sc << head << "N1,N2,N_used,runs,phi,e,valid,status" << tail;
  so << head << "m_prev,m_i,runs,theta_Z,Z_sum,Z_mean,valid,status" << tail;
  fx << head << "N,runs,R,A,valid,status" << tail;
  for (const auto& [key, group] : library.groups()) {
    if (!group.valid) {
      t.problems.push_back(key.label() + ": its runs cannot be combined: " + group.reason);
      continue;
    }
    const RunEvaluation ev = evaluateRun(library, key, group.mean, /*final=*/true, defs, band);
    const std::string runs = std::to_string(group.runs);
    if (key.swarm_size > 1) {
      const Scalability& s = ev.scalability;
      const Evaluated& st = ev.scalability_status;
      sc << describe(key) << ',' << st.reference_size << ',' << key.swarm_size << ',' << s.n_used << ','
         << runs << ',' << num(s.phi.value) << ',' << num(s.e.value) << ',' << (st.valid ? 1 : 0) << ','
         << csvQuoted(st.status) << setup(key);
      note(t, key, "e", st);
      const SelfOrganization& z = ev.self_organization;
      const Evaluated& zt = ev.self_organization_status;
      const double theta = z.theta.value.empty() ? 0.0 : z.theta.value.back();
      so << describe(key) << ',' << zt.reference_size << ',' << key.swarm_size << ',' << runs << ','
         << num(theta) << ',' << num(z.z_sum.value) << ',' << num(z.z_mean.value) << ',' << (zt.valid ? 1 : 0)
         << ',' << csvQuoted(zt.status) << setup(key);
      note(t, key, "Z", zt);
    }
    if (!key.environment.ideal()) {
      const Evaluated& r = ev.reactivity_status;
      const Evaluated& a = ev.adaptability_status;
      const bool valid = r.valid && a.valid;
      fx << describe(key) << ',' << key.swarm_size << ',' << runs << ',' << num(ev.reactivity.distance.value)
         << ',' << num(ev.adaptability.distance.value) << ',' << (valid ? 1 : 0) << ','
         << csvQuoted(valid ? std::string("ok") : (r.valid ? a.status : r.status)) << setup(key);
      note(t, key, "R", r);
      note(t, key, "A", a);
    }
  }
  std::ostringstream rb, rr;
  rb << robustnessHead("runs");
  rr << robustnessHead("seed");
  for (const auto& [key, group] : library.groups()) {
    if (!group.valid) continue;
    const RobustnessEvaluation ev =
        evaluateRobustness(library, key, group.mean, std::nullopt, true, defs, band);
    if (!ev.saa_applies && !ev.pd_applies) continue;
    robustnessRows(rb, key, std::to_string(group.runs), ev);
    if (ev.saa_applies) note(t, key, "SAA robustness", ev.saa_status);
    if (ev.pd_applies) note(t, key, "PD robustness", ev.pd_status);
    for (const RunRecord* run : library.runs(key))
      robustnessRows(rr, key, std::to_string(run->seed),
                     evaluateRobustness(library, key, run->series, run->seed, true, defs, band));
  }
  t.robustness = rb.str();
  t.robustness_runs = rr.str();
  t.scalability = sc.str();
  t.self_organization = so.str();
  t.flexibility = fx.str();
  return t;
}

std::string groupSeriesCsv(const RunLibrary& library) {
  std::ostringstream out;
  out.precision(10);
  out << "controller,arena,swarm_size,waveform,beta,alpha,runs,sample,tick_end,P_mean,P_ci95,p_mean,p_ci95,"
         "n_ca_mean,n_ca_ci95,sample_interval,identity\n";
  for (const auto& [key, group] : library.groups()) {
    if (!group.valid) continue;
    const RunSeries& m = group.mean;
    const RunSeries& c = group.ci95;
    for (std::size_t k = 0; k < m.P.size(); ++k)
      out << key.controller << ',' << key.arena << ',' << key.swarm_size << ',' << key.environment.waveform
          << ',' << key.environment.beta << ',' << key.environment.alpha << ',' << group.runs << ',' << k
          << ',' << (k + 1) * static_cast<uint64_t>(m.interval) - 1 << ',' << m.P[k] << ',' << at(c.P, k)
          << ',' << at(m.p, k) << ',' << at(c.p, k) << ',' << at(m.n_ca, k) << ',' << at(c.n_ca, k) << ','
          << m.interval << ',' << key.identity() << '\n';
  }
  return out.str();
}

}  // namespace swarm_forage
