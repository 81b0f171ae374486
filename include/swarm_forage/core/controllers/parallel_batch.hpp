#pragma once
// A controller range run as several contiguous sub-ranges on a worker pool. Controllers are split
// invariant (a robot's commands depend only on its own state and readings), so the commands and status
// are the same as one batch's for any thread count.
#include <functional>
#include <memory>
#include <vector>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"

namespace swarm_forage {

class ParallelBatch : public ControllerBatch {
 public:
  /// make(first_id, count) builds one sub-range's batch.
  using Factory = std::function<std::unique_ptr<ControllerBatch>(uint32_t first_id, uint32_t count)>;
  ParallelBatch(const Factory& make, uint32_t first_id, uint32_t count, std::shared_ptr<WorkerPool> pool);

  std::string name() const override { return parts_.front().batch->name(); }
  void step(uint64_t tick, const SensorData& sensors, CommandData& commands,
            ControllerStatus& status) override;
  bool checkpointable() const override { return parts_.front().batch->checkpointable(); }
  /// The parts in order: the same bytes as one batch of the range (ControllerBatch::persist).
  void persist(StateArchive& a) override {
    for (Part& p : parts_) p.batch->persist(a);
  }

 private:
  struct Part {
    std::unique_ptr<ControllerBatch> batch;
    CommandData commands;
    ControllerStatus status;
  };
  uint32_t first_id_, count_;
  std::shared_ptr<WorkerPool> pool_;
  std::vector<Part> parts_;
};

}  // namespace swarm_forage
