#include "swarm_forage/ros/params/run_params.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/ros/runs/run_recorder.hpp"

namespace swarm_forage {

RunDescription readRunDescription(const ParamSource& p, const std::string& external) {
  RunDescription run;
  run.world = readWorldConfig(p);
  run.controller = paramController(p, external);
  run.external = external;
  run.ticks = static_cast<uint64_t>(readParam<int>(p, "ticks"));
  return run;
}

std::string readExternalController(const ParamSource& p) {
  const std::string name = readParam<std::string>(p, "external_controller");
  const auto& kinds = controllerNames();
  if (!std::all_of(name.begin(), name.end(), [](unsigned char c) { return std::isalnum(c) || c == '_'; }))
    throw ParameterError("~external_controller must be a name of letters, digits and '_' (got '" + name +
                         "')");
  if (std::find(kinds.begin(), kinds.end(), name) != kinds.end())
    throw ParameterError(
        "~external_controller '" + name +
        "' is a controller of this build: run it with ~controller alone, or give the external "
        "one another name");
  return name;
}

RunOutputs RunOutputs::read(const ParamSource& p, const std::string& tilde) {
  RunOutputs o;
  o.record_every = static_cast<uint32_t>(readParam<int>(p, "record_every"));
  o.bag = readParam<std::string>(p, "bag");
  o.bag_dir = readParam<std::string>(p, "bag_dir");
  if (!o.bag.empty() && !o.bag_dir.empty())
    throw ParameterError(tilde + "bag and " + tilde +
                         "bag_dir are both set: give a bag's path, or a folder to name bags in");
  o.overwrite = readParam<bool>(p, "overwrite");
  if (o.bag_dir.empty()) explicitBagPolicy("bag", o.bag, o.overwrite);  // an existing bag is refused now
  o.label = readParam<std::string>(p, "label");
  o.compression = readParam<std::string>(p, "compression");
  o.outcome = readParam<std::string>(p, "outcome");
  if (!o.outcome.empty() && !std::ofstream(o.outcome, std::ios::app))
    throw ParameterError(tilde + "outcome '" + o.outcome + "' cannot be appended to (a writable file path)");
  return o;
}

}  // namespace swarm_forage
