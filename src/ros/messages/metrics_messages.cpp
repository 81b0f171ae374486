#include "swarm_forage/ros/messages/metrics_messages.hpp"

namespace swarm_forage {

namespace {
/// The fields every metric message has.
template <typename M>
M common(const SampleContext& c) {
  M m;
  m.header.stamp = c.stamp;
  m.run = c.run;
  m.controller = c.key.controller;
  m.arena = c.key.arena;
  m.environment = c.key.environment.label();
  m.tick_end = c.tick_end;
  m.final = c.final;
  m.definitions = definitionsName(c.definitions);
  return m;
}

template <typename M>
M header(const SampleContext& c, const Evaluated& status) {
  M m = common<M>(c);
  m.valid = status.valid;
  m.status = status.status;
  return m;
}

double last(const MetricSeries& s) { return s.value.empty() ? 0.0 : s.value.back(); }
}  // namespace

ScalabilityMetric toMsg(const SampleContext& c, const Scalability& value, const Evaluated& status) {
  auto m = header<ScalabilityMetric>(c, status);
  m.N1 = status.reference_size;
  m.N2 = c.key.swarm_size;
  m.N_used = value.n_used;
  m.phi = value.phi.value;
  m.e = value.e.value;
  m.e_t = value.e_t.value;
  m.e_t_valid.assign(value.e_t.sample_valid.begin(), value.e_t.sample_valid.end());
  return m;
}

SelfOrganizationMetric toMsg(const SampleContext& c, const SelfOrganization& value, const Evaluated& status) {
  auto m = header<SelfOrganizationMetric>(c, status);
  m.m_i = c.key.swarm_size;
  m.m_prev = status.reference_size;
  m.P_lost = last(value.p_lost_cur);
  m.theta_Z = last(value.theta);
  m.Z_sum = value.z_sum.value;
  m.Z_mean = value.z_mean.value;
  return m;
}

FlexibilityMetric toMsg(const SampleContext& c, const Flexibility& value, const Evaluated& status) {
  auto m = header<FlexibilityMetric>(c, status);
  m.N = c.key.swarm_size;
  m.waveform = c.key.environment.waveform;
  m.beta = c.key.environment.beta;
  m.distance = value.distance.value;
  m.ideal = value.ideal;
  return m;
}

Robustness toMsg(const SampleContext& c, const RobustnessEvaluation& ev) {
  auto m = common<Robustness>(c);
  m.N = c.key.swarm_size;
  m.noise = ev.words.noise;
  m.noise_level = ev.words.noise_level;
  const PopulationRates& r = ev.words.population;
  m.death = r.death;
  m.birth = r.birth;
  m.malfunction = r.malfunction;
  m.repair = r.repair;
  m.max_size = r.max_size;
  m.saa_distance = ev.saa.distance.value;
  m.saa_normalized = ev.saa.normalized.value;
  m.saa_valid = ev.saa_status.valid;
  m.saa_status = ev.saa_status.status;
  m.saa_reference = ev.saa_reference;
  m.arrival_rate = r.arrival();
  m.service_rate = r.service();
  m.T = ev.T;
  m.T_bar = ev.pd.time_out.value;
  m.P = ev.P;
  m.P_reference = ev.P_reference;
  m.theta = ev.pd.theta.value;
  m.pd_normalized = ev.pd.normalized.value;
  m.pd_valid = ev.pd_status.valid;
  m.pd_status = ev.pd_status.status;
  m.pd_reference = ev.pd_reference;
  return m;
}

}  // namespace swarm_forage
