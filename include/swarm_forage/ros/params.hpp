#pragma once
// Reading private ~parameters once, with validation that names the parameter and its valid range.
#include <ros/node_handle.h>

#include <string>
#include <vector>

#include "swarm_forage/core/config.hpp"

namespace swarm_forage {

/// Reads ~name (default when unset); throws ParameterError when it is set with the wrong type.
template <typename T>
T param(const ros::NodeHandle& pnh, const std::string& name, const T& fallback) {
  if (!pnh.hasParam(name)) return fallback;
  T value;
  if (!pnh.getParam(name, value))
    throw ParameterError("~" + name + " has the wrong type (" + pnh.resolveName(name) + ")");
  return value;
}

/// Reads a number in [lo, hi]; throws ParameterError "~name must be in [lo, hi] (got v)".
double paramInRange(const ros::NodeHandle& pnh, const std::string& name, double fallback, double lo,
                    double hi);
int paramInRange(const ros::NodeHandle& pnh, const std::string& name, int fallback, int lo, int hi);

/// Reads a string that must be one of `valid`.
std::string paramOneOf(const ros::NodeHandle& pnh, const std::string& name, const std::string& fallback,
                       const std::vector<std::string>& valid);

/// Resolves ~arena: a name of config/arenas/NAME.yaml or a path to a YAML file.
ArenaConfig loadArena(const std::string& name_or_path);

}  // namespace swarm_forage
