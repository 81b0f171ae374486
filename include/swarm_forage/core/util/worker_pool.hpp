#pragma once
// A fixed set of threads that run numbered tasks. Which thread runs a task never matters: callers
// give every task its own output (or per-worker scratch), so results are the same for any thread count,
// and the pool may run a job on the calling thread alone while other processes want the cores.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "swarm_forage/core/util/core_contention.hpp"

namespace swarm_forage {

class WorkerPool {
 public:
  /// `threads` = 0: one per core. The calling thread is one of them. `waited`: see CoreContention (a
  /// test gives its own).
  explicit WorkerPool(unsigned threads = 1, CoreContention::Waited waited = {});
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  unsigned threads() const { return threads_; }
  /// The number of cores, as `threads` = 0 means.
  static unsigned cores();
  /// Jobs so far that more than one thread could share (more than one task), and how many of them ran on
  /// the calling thread alone because other processes wanted the cores.
  uint64_t jobs() const { return contention_.jobs(); }
  uint64_t jobsAlone() const { return contention_.jobsAlone(); }
  /// jobsAlone() / jobs() in percent (0 before any job); any thread may call it.
  double percentAlone() const {
    const uint64_t jobs = contention_.jobs();
    return jobs ? 100.0 * static_cast<double>(contention_.jobsAlone()) / static_cast<double>(jobs) : 0.0;
  }

  /// Calls f(task, worker) once for every task in [0, tasks), worker < threads(), and returns when all
  /// are done. The first exception a task throws is rethrown here. Each worker starts on its own
  /// contiguous share of the tasks, the same share in every job of as many tasks (so the data a task
  /// writes stays in one core's cache from job to job), and then takes what is left of the others'.
  template <typename F>
  void run(std::size_t tasks, F&& f) {
    if (threads_ == 1 || tasks <= 1 || !contention_.shareJob(threads_)) {
      for (std::size_t t = 0; t < tasks; ++t) f(t, 0u);
      return;
    }
    dispatch(tasks, std::function<void(std::size_t, unsigned)>(std::forward<F>(f)));
  }

 private:
  void dispatch(std::size_t tasks, std::function<void(std::size_t, unsigned)> f);
  void work(unsigned worker);  // claims tasks of the current job until none is left
  void loop(unsigned worker);

  unsigned threads_;
  CoreContention contention_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::function<void(std::size_t, unsigned)> job_;
  struct alignas(64) Share {  // a worker's tasks: the next to claim, and the end (one cache line each)
    std::atomic<std::size_t> next{0};
    std::size_t end = 0;
  };
  std::vector<Share> shares_;
  std::atomic<uint64_t> generation_{0};
  std::atomic<unsigned> busy_{0};  // workers still in the current job
  bool stop_ = false;
  std::exception_ptr error_;
};

}  // namespace swarm_forage
