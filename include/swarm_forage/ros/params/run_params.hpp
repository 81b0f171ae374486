#pragma once
// The parameters of a run that world_node and run_experiment both read, read by one piece of code.
#include <string>

#include "swarm_forage/core/run/run_records.hpp"
#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

/// The world's model parameters, ~controller and ~ticks. `external` (readExternalController) is accepted as
/// ~controller too: the run is then served by nodes outside this build.
RunDescription readRunDescription(const ParamSource& p, const std::string& external = "");
/// world_node's ~external_controller: the name of a controller served by nodes outside this build (a rospy
/// node), or "" (docs/rospy-controller.md). Throws ParameterError for a name this build already has.
std::string readExternalController(const ParamSource& p);

/// Where a node's runs go: ~record_every, ~bag (one path) or ~bag_dir (a folder whose bags are named by
/// runBagPath), ~overwrite, ~compression, ~label (world/provenance) and ~outcome (a YAML list of how runs
/// ended).
struct RunOutputs {
  std::string bag, bag_dir, compression = "none", label, outcome;
  bool overwrite = false;
  uint32_t record_every = 250;  // robots and blocks every that many ticks (RunSchedule)
  /// Reads and checks them; `tilde` ("~" for a node, "" for run_experiment) prefixes names in messages.
  /// Throws ParameterError (both ~bag and ~bag_dir, an existing ~bag without ~overwrite, an ~outcome
  /// that cannot be appended to).
  static RunOutputs read(const ParamSource& p, const std::string& tilde);
};

}  // namespace swarm_forage
