// The built-in controllers' persistent state for checkpoints (docs/runs-and-bags.md), robot by robot: a
// range split into parts over threads saves the same bytes as one batch. Each kind is checkpointable only
// as itself, so a plugin deriving from one with state of its own gets the clear refusal, not a silent gap.
#include <typeinfo>

#include "swarm_forage/core/controllers/crw.hpp"
#include "swarm_forage/core/controllers/gp_dpo.hpp"
#include "swarm_forage/core/util/state_archive.hpp"

namespace swarm_forage {

// The structs the controllers archive, field by field (StateArchive::io).
void persistValue(StateArchive& a, Remembered& r) { a.io(r.id, r.x, r.y, r.rho); }
void persistValue(StateArchive& a, TaskEstimates& e) { a.io(e.e[0], e.e[1], e.e[2]); }

void StallTracker::persist(StateArchive& a, uint32_t local) { a.io(x_[local], y_[local], since_[local]); }

void ObjectMemory::persist(StateArchive& a, uint32_t local) { a.io(entries_[local]); }

void ForagerBatch::persist(StateArchive& a) {
  if (!checkpointable()) ControllerBatch::persist(a);  // throws, naming the kind
  for (uint32_t local = 0; local < count(); ++local) persistRobot(a, local);
}

void ForagerBatch::persistRobot(StateArchive& a, uint32_t local) {
  a.io(state_[local], state_ticks_[local], wander_angle_[local]);
  stalls_.persist(a, local);
  materializeHeading(local);  // saved as taken: the checkpoint holds the estimate itself
  a.io(drive_speed_[local], coasting_[local], prev_x_[local], prev_y_[local], heading_est_[local]);
}

bool CrwBatch::checkpointable() const { return typeid(*this) == typeid(CrwBatch); }

bool DpoBatch::checkpointable() const { return typeid(*this) == typeid(DpoBatch); }

void DpoBatch::persistRobot(StateArchive& a, uint32_t local) {
  ForagerBatch::persistRobot(a, local);
  blocks_.persist(a, local);
  a.io(target_[local], last_collision_[local], recovery_phase_[local], recovery_ticks_[local],
       recovery_heading_[local], arrival_last_[local]);
}

bool GpDpoBatch::checkpointable() const { return typeid(*this) == typeid(GpDpoBatch); }

void GpDpoBatch::persistRobot(StateArchive& a, uint32_t local) {
  DpoBatch::persistRobot(a, local);
  a.io(task_[local], last_subtask_[local], task_start_[local], est_[local], partition_[local]);
  caches_.persist(a, local);
}

}  // namespace swarm_forage
