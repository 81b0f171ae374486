#pragma once
// The live metric messages of one sample, from a run's evaluation against the library.
#include <swarm_forage/FlexibilityMetric.h>
#include <swarm_forage/Robustness.h>
#include <swarm_forage/ScalabilityMetric.h>
#include <swarm_forage/SelfOrganizationMetric.h>

#include "swarm_forage/core/metrics/robustness_evaluation.hpp"
#include "swarm_forage/core/metrics/run_library.hpp"

namespace swarm_forage {

/// What every metric message of one sample shares.
struct SampleContext {
  ros::Time stamp;
  uint32_t run = 0;
  RunKey key;
  uint64_t tick_end = 0;
  bool final = false;
  Definitions definitions = Definitions::kPaper;
};

ScalabilityMetric toMsg(const SampleContext& c, const Scalability& value, const Evaluated& status);
SelfOrganizationMetric toMsg(const SampleContext& c, const SelfOrganization& value, const Evaluated& status);
FlexibilityMetric toMsg(const SampleContext& c, const Flexibility& value, const Evaluated& status);
Robustness toMsg(const SampleContext& c, const RobustnessEvaluation& ev);

}  // namespace swarm_forage
