#pragma once
// GP-DPO task-allocation arithmetic (docs/design-model.md, Controllers), as pure functions: the
// execution-time moving average, the partition probability, the subtask switch probability and the abort
// probability.
#include <cmath>

namespace swarm_forage {

/// The logistic function 1 / (1 + e^-x).
double logistic(double x);

/// est <- (1 - weight) est + weight measured (the design: weight 0.8).
double emaUpdate(double estimate, double measured, double weight = 0.8);

/// theta = r (E_g / (E_h + E_c) - 1) if E_g > E_h + E_c, else r (1 - (E_h + E_c) / E_g); 0 when the
/// denominator is not positive (no information).
double partitionTheta(double e_generalist, double e_harvester, double e_collector, double r);

/// P_partition = logistic(theta): the probability of taking a subtask rather than the generalist task.
double partitionProbability(double e_generalist, double e_harvester, double e_collector, double r);

/// Probability of switching from the last subtask (estimate e_from) to the other one (e_to):
/// logistic(k (e_from / e_to - offset)) when e_to > e_from, else logistic(k (1 - offset));
/// 0.5 when either estimate is missing (not positive). The design: k = 8, offset = 1.25.
double subtaskSwitchProbability(double e_from, double e_to, double reactivity = 8.0, double offset = 1.25);

/// p = 1 / (1 + exp(k |t_exec / E - offset|)) (the design: k = 8, offset = 3); 0 when E is not positive.
double abortProbability(double t_exec, double estimate, double reactivity = 8.0, double offset = 3.0);
/// abortProbability(t_exec, estimate, reactivity, offset) > u, without exp where a bound decides it (almost
/// always: a task's time is seldom near offset x its estimate). Inline: once per robot at the interface.
inline bool aborts(double u, double t_exec, double estimate, double reactivity = 8.0, double offset = 3.0) {
  // exp(z) >= 1 + z + z^2/2 + z^3/6 for z >= 0, so p <= 1 / (2 + z + z^2/2 + z^3/6); the margin covers
  // the roundings of exp and of the division (relative errors near 1e-16).
  const double z = reactivity * std::fabs(t_exec / estimate - offset);
  if (estimate > 0 && z >= 0 && u * (2.0 + z * (1.0 + z * (0.5 + z / 6.0))) > 1.0 + 1e-9) return false;
  return abortProbability(t_exec, estimate, reactivity, offset) > u;
}

}  // namespace swarm_forage
