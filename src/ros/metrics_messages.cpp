#include "swarm_forage/ros/metrics_messages.hpp"

namespace swarm_forage {

namespace {
template <typename M>
M header(const SampleContext& c, const Evaluated& status) {
  M m;
  m.header.stamp = c.stamp;
  m.run = c.run;
  m.controller = c.key.controller;
  m.arena = c.key.arena;
  m.environment = c.key.environment.label();
  m.tick_end = c.tick_end;
  m.final = c.final;
  m.definitions = definitionsName(c.definitions);
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

}  // namespace swarm_forage
