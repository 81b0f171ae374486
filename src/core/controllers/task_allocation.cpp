#include "swarm_forage/core/controllers/task_allocation.hpp"

#include <cmath>

namespace swarm_forage {

double logistic(double x) { return 1.0 / (1.0 + std::exp(-x)); }

double emaUpdate(double estimate, double measured, double weight) {
  return (1.0 - weight) * estimate + weight * measured;
}

double partitionTheta(double e_generalist, double e_harvester, double e_collector, double r) {
  const double subtasks = e_harvester + e_collector;
  if (e_generalist > subtasks) return subtasks > 0 ? r * (e_generalist / subtasks - 1.0) : 0.0;
  return e_generalist > 0 ? r * (1.0 - subtasks / e_generalist) : 0.0;
}

double partitionProbability(double e_generalist, double e_harvester, double e_collector, double r) {
  return logistic(partitionTheta(e_generalist, e_harvester, e_collector, r));
}

double subtaskSwitchProbability(double e_from, double e_to, double reactivity, double offset) {
  if (!(e_from > 0 && e_to > 0)) return 0.5;
  return e_to > e_from ? logistic(reactivity * (e_from / e_to - offset))
                       : logistic(reactivity * (1.0 - offset));
}

double abortProbability(double t_exec, double estimate, double reactivity, double offset) {
  if (!(estimate > 0)) return 0.0;
  return 1.0 / (1.0 + std::exp(reactivity * std::fabs(t_exec / estimate - offset)));
}

}  // namespace swarm_forage
