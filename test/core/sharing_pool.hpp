#pragma once
// A worker pool that never finds the cores contended, so that its jobs are shared between its threads
// even on a busy test machine (or with 3 threads on 2 cores): the tests that compare thread counts
// then compare them, rather than runs that fell back to one thread.
#include <cstdint>
#include <memory>

#include "swarm_forage/core/util/worker_pool.hpp"

namespace swarm_forage {

inline std::shared_ptr<WorkerPool> sharingPool(unsigned threads) {
  return std::make_shared<WorkerPool>(threads, [] { return uint64_t{0}; });
}

}  // namespace swarm_forage
