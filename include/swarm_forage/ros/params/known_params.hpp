#pragma once
// Every node's private parameters, from the parameter table (param_table.hpp): the start-up check refuses
// any other key in the node's namespace, listing the valid ones.
#include <ros/node_handle.h>

#include <string>
#include <vector>

namespace swarm_forage {

/// readCondition's keys, and the controller constants' sections (<kind>/ for every controller kind found:
/// their keys are checked by readControllerConfigs).
std::vector<std::string> conditionParams();
std::vector<std::string> controllerSections();

/// The names in `given` not among `known`; a known name ending in '/' admits a whole section.
std::vector<std::string> unknownNames(const std::vector<std::string>& given,
                                      const std::vector<std::string>& known);

/// `known` as one line: "a, b, c".
std::string joinNames(const std::vector<std::string>& known);

/// Throws ParameterError naming the first parameter in pnh's private namespace that is not among `known`
/// (a typo such as ~n_robts would otherwise leave a default in force unseen), with the valid ones.
void refuseUnknownParams(const ros::NodeHandle& pnh, const std::vector<std::string>& known,
                         const std::string& node);

}  // namespace swarm_forage
