#include "swarm_forage/core/controllers/parallel_batch.hpp"

#include <algorithm>

namespace swarm_forage {

namespace {
constexpr uint32_t kMinPart = 512;  // robots: smaller parts cost more in dispatch than they save
}

ParallelBatch::ParallelBatch(const Factory& make, uint32_t first_id, uint32_t count,
                             std::shared_ptr<WorkerPool> pool)
    : first_id_(first_id), count_(count), pool_(std::move(pool)) {
  // A few parts per thread, so that a thread finishing early takes another.
  const uint32_t parts = std::max(1u, std::min(4 * pool_->threads(), count / kMinPart));
  for (uint32_t k = 0; k < parts; ++k) {
    const uint32_t begin = static_cast<uint32_t>(uint64_t{count} * k / parts);
    const uint32_t end = static_cast<uint32_t>(uint64_t{count} * (k + 1) / parts);
    parts_.push_back({make(first_id + begin, end - begin), {}, {}});
  }
}

void ParallelBatch::step(uint64_t tick, const SensorData& sensors, CommandData& commands,
                         ControllerStatus& status) {
  pool_->run(parts_.size(), [&](std::size_t k, unsigned) {
    Part& p = parts_[k];
    p.batch->step(tick, sensors, p.commands, p.status);
  });
  commands.first_id = first_id_;
  if (commands.size() != count_) commands.resize(count_);
  status = parts_.front().status;
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    const Part& p = parts_[k];
    const std::size_t at = p.commands.first_id - first_id_;
    std::copy(p.commands.left.begin(), p.commands.left.end(), commands.left.begin() + at);
    std::copy(p.commands.right.begin(), p.commands.right.end(), commands.right.begin() + at);
    std::copy(p.commands.request.begin(), p.commands.request.end(), commands.request.begin() + at);
    std::copy(p.commands.task.begin(), p.commands.task.end(), commands.task.begin() + at);
    if (k == 0) continue;
    status.in_avoidance += p.status.in_avoidance;
    status.stalled += p.status.stalled;
    for (std::size_t s = 0; s < status.state_counts.size(); ++s)
      status.state_counts[s] += p.status.state_counts[s];
    status.tasks.generalists += p.status.tasks.generalists;
    status.tasks.harvesters += p.status.tasks.harvesters;
    status.tasks.collectors += p.status.tasks.collectors;
  }
}

}  // namespace swarm_forage
