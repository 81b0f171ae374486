#pragma once
// Whether other processes want the cores a worker pool runs on, and so whether its next job should be
// shared between its threads or run on the calling thread alone. A shared job waits for its slowest
// thread: one that has lost its core to another process holds the job for a scheduler time slice
// (milliseconds), and the calling thread alone is faster. docs/performance.md, "Sharing the cores".
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

namespace swarm_forage {

class CoreContention {
 public:
  /// Nanoseconds the pool's threads have spent so far ready to run but without a core, summed.
  using Waited = std::function<uint64_t()>;
  /// `waited` empty: the kernel's run delay (schedstat) of the calling thread and the registered ones, or,
  /// with SWARM_FORAGE_SHARE_JOBS=always in the environment, never contended (another value of it throws
  /// std::invalid_argument naming it).
  explicit CoreContention(Waited waited = {});
  ~CoreContention();
  CoreContention(const CoreContention&) = delete;
  CoreContention& operator=(const CoreContention&) = delete;

  /// A worker thread adds its own run delay to the default `waited`.
  void addThisThread();
  /// Called by the calling thread for each job that `threads` threads could share: false while the
  /// cores are contended. Every window of shared jobs reads how long the threads waited for a core;
  /// above a share of the window's time in two windows in a row, the jobs run alone for a hold, which
  /// doubles while the window after each hold still finds the cores contended.
  bool shareJob(unsigned threads);
  /// Any thread may read these (diagnostics).
  uint64_t jobs() const { return jobs_.load(std::memory_order_relaxed); }
  uint64_t jobsAlone() const { return alone_.load(std::memory_order_relaxed); }

 private:
  uint64_t threadsWaited();

  Waited waited_;
  std::mutex mutex_;          // guards fds_
  std::vector<int> fds_;      // the registered threads' /proc/thread-self/schedstat
  uint64_t last_waited_ = 0;  // at the last reading
  std::chrono::steady_clock::time_point last_time_;
  std::atomic<uint64_t> jobs_{0}, alone_{0};  // written by the calling thread only
  uint64_t until_ = 0;                        // the job that next reads
  uint64_t hold_;
  bool solo_ = false;
  bool probing_ = false;  // this window follows a hold
  bool strike_ = false;   // the last window found the cores contended
};

}  // namespace swarm_forage
