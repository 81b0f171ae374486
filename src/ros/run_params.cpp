#include "swarm_forage/ros/run_params.hpp"

#include <fstream>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/ros/run_recorder.hpp"

namespace swarm_forage {

RunDescription readRunDescription(const ParamSource& p) {
  RunDescription run;
  run.world = readWorldConfig(p);
  run.controller = paramController(p);
  run.ticks = static_cast<uint64_t>(paramInRange(p, "ticks", 50000, 1, 2000000000));
  return run;
}

RunOutputs RunOutputs::read(const ParamSource& p, const std::string& tilde) {
  RunOutputs o;
  o.record_every = static_cast<uint32_t>(paramInRange(p, "record_every", 250, 1, 1000000));
  o.bag = param<std::string>(p, "bag", "");
  o.bag_dir = param<std::string>(p, "bag_dir", "");
  if (!o.bag.empty() && !o.bag_dir.empty())
    throw ParameterError(tilde + "bag and " + tilde +
                         "bag_dir are both set: give a bag's path, or a folder to name bags in");
  o.overwrite = param<bool>(p, "overwrite", false);
  if (o.bag_dir.empty()) explicitBagPolicy("bag", o.bag, o.overwrite);  // an existing bag is refused now
  o.label = param<std::string>(p, "label", "");
  o.compression = paramOneOf(p, "compression", "none", RunRecorder::compressions());
  o.outcome = param<std::string>(p, "outcome", "");
  if (!o.outcome.empty() && !std::ofstream(o.outcome, std::ios::app))
    throw ParameterError(tilde + "outcome '" + o.outcome + "' cannot be appended to (a writable file path)");
  return o;
}

}  // namespace swarm_forage
