#pragma once
// Translation between core structures and the batched messages: sensors, commands and status, one per tick.
#include <swarm_forage/CommandBatch.h>
#include <swarm_forage/SensorBatch.h>
#include <swarm_forage/SwarmStatus.h>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

void toMsg(const SensorData& s, SensorBatch& msg);
void fromMsg(const SensorBatch& msg, SensorData& s);
void toMsg(const CommandData& c, CommandBatch& msg);
/// Copies a command batch into `all` (which covers the whole swarm) at its first_id.
void mergeInto(const CommandBatch& msg, CommandData& all);
void toMsg(const ControllerStatus& s, SwarmStatus& msg);
void fromMsg(const SwarmStatus& msg, ControllerStatus& s);

}  // namespace swarm_forage
