// The private parameters every node knows: the parameter table's rows (param_table.cpp) and what its
// dynamic_reconfigure servers write; see known_params.hpp.
#include "swarm_forage/ros/params/known_params.hpp"

#include <swarm_forage/EnvironmentConfig.h>
#include <swarm_forage/NoiseConfig.h>
#include <swarm_forage/PopulationRatesConfig.h>
#include <swarm_forage/WorldPaceConfig.h>

#include <algorithm>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/ros/nodes/controller_ros.hpp"
#include "swarm_forage/ros/nodes/environment_ros.hpp"
#include "swarm_forage/ros/nodes/metrics_ros.hpp"
#include "swarm_forage/ros/params/param_table.hpp"
#include "swarm_forage/ros/params/params.hpp"
#include "swarm_forage/ros/world_node/world_ros.hpp"

namespace swarm_forage {

namespace {
std::vector<std::string> operator+(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// dynamic_reconfigure's server writes its fields (and last_change) into the node's private namespace.
// `ns`: the server's namespace under the node's ("noise/").
template <typename Config>
std::vector<std::string> reconfigureParams(const std::string& ns = "") {
  std::vector<std::string> names;
  for (const auto& d : Config::__getParamDescriptions__()) names.push_back(ns + d->name);
  return names;
}

std::vector<std::string> sortedUnique(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}
}  // namespace

std::vector<std::string> conditionParams() {
  std::vector<std::string> names;
  for (const ConditionParameter& c : conditionParameters()) names.push_back(c.name);
  return names;
}

std::vector<std::string> controllerSections() {
  std::vector<std::string> names;
  // Every kind found, loaded or not: a graph's parameters may hold the constants of a kind it does not run.
  for (const std::string& s : availableControllers()) names.push_back(s + "/");
  return names;
}

// The table's rows, and the fields dynamic_reconfigure's servers write into the node's namespace.
std::vector<std::string> WorldRos::parameterNames() {
  return sortedUnique(knownParams(kWorldNode) + reconfigureParams<WorldPaceConfig>() +
                      reconfigureParams<NoiseConfig>("noise/") +
                      reconfigureParams<PopulationRatesConfig>("population/"));
}

std::vector<std::string> ControllerRos::parameterNames() {
  return sortedUnique(knownParams(kControllerNode));
}

std::vector<std::string> EnvironmentRos::parameterNames() {
  return sortedUnique(knownParams(kEnvironmentNode) + reconfigureParams<EnvironmentConfig>());
}

std::vector<std::string> MetricsRos::parameterNames() { return sortedUnique(knownParams(kMetricsNode)); }

std::vector<std::string> unknownNames(const std::vector<std::string>& given,
                                      const std::vector<std::string>& known) {
  std::vector<std::string> out;
  for (const std::string& n : given) {
    const bool ok = std::any_of(known.begin(), known.end(), [&](const std::string& k) {
      return k == n || (!k.empty() && k.back() == '/' && n.compare(0, k.size(), k) == 0);
    });
    if (!ok) out.push_back(n);
  }
  return out;
}

std::string joinNames(const std::vector<std::string>& known) {
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  return list;
}

void refuseUnknownParams(const ros::NodeHandle& pnh, const std::vector<std::string>& known,
                         const std::string& node) {
  std::vector<std::string> all;
  if (!ros::param::getParamNames(all)) return;  // no master: ros::init would not have got here
  const std::string prefix = pnh.getNamespace() + "/";
  std::vector<std::string> mine;
  for (const std::string& name : all)
    if (name.compare(0, prefix.size(), prefix) == 0) mine.push_back(name.substr(prefix.size()));
  std::sort(mine.begin(), mine.end());
  const std::vector<std::string> unknown = unknownNames(mine, known);
  if (unknown.empty()) return;
  throw ParameterError("~" + unknown.front() + " (" + prefix + unknown.front() + ") is not a parameter of " +
                       node + "; valid: " + joinNames(known));
}

}  // namespace swarm_forage
