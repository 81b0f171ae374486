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

void StallTracker::persist(StateArchive& a, uint32_t local) {
  a.io(x_[local]);
  a.io(y_[local]);
  a.io(since_[local]);
}

void ObjectMemory::persist(StateArchive& a, uint32_t local) { a.io(entries_[local]); }

void ForagerBatch::persist(StateArchive& a) {
  if (!checkpointable()) ControllerBatch::persist(a);  // throws, naming the kind
  for (uint32_t local = 0; local < count(); ++local) persistRobot(a, local);
}

void ForagerBatch::persistRobot(StateArchive& a, uint32_t local) {
  a.io(state_[local]);
  a.io(state_ticks_[local]);
  a.io(wander_angle_[local]);
  stalls_.persist(a, local);
  a.io(drive_speed_[local]);
  a.io(coasting_[local]);
  a.io(prev_x_[local]);
  a.io(prev_y_[local]);
  a.io(heading_est_[local]);
}

bool CrwBatch::checkpointable() const { return typeid(*this) == typeid(CrwBatch); }

bool DpoBatch::checkpointable() const { return typeid(*this) == typeid(DpoBatch); }

void DpoBatch::persistRobot(StateArchive& a, uint32_t local) {
  ForagerBatch::persistRobot(a, local);
  blocks_.persist(a, local);
  a.io(target_[local]);
  a.io(last_collision_[local]);
  a.io(recovery_phase_[local]);
  a.io(recovery_ticks_[local]);
  a.io(recovery_heading_[local]);
  a.io(arrival_last_[local]);
}

bool GpDpoBatch::checkpointable() const { return typeid(*this) == typeid(GpDpoBatch); }

void GpDpoBatch::persistRobot(StateArchive& a, uint32_t local) {
  DpoBatch::persistRobot(a, local);
  a.io(task_[local]);
  a.io(last_subtask_[local]);
  a.io(task_start_[local]);
  a.io(est_[local]);
  a.io(partition_[local]);
  caches_.persist(a, local);
}

}  // namespace swarm_forage
