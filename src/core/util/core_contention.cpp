#include "swarm_forage/core/util/core_contention.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace swarm_forage {

namespace {

// Measured on 2 cores (docs/performance.md): idle, the threads wait for a core under 1 % of a window's
// time, with bursts up to 25 % that last one window; with one busy process more than cores, 45-50 %,
// with two 50-90 %.
constexpr uint64_t kWindow = 32;                      // shared jobs per reading
constexpr double kContended = 0.15;                   // share of the window's thread time spent waiting
constexpr uint64_t kMinHold = 256, kMaxHold = 16384;  // jobs run alone

// The second field of a schedstat file: the task's run delay in nanoseconds; 0 if it cannot be read.
uint64_t runDelay(int fd) {
  char text[128];
  const ssize_t n = fd >= 0 ? pread(fd, text, sizeof text - 1, 0) : -1;
  if (n <= 0) return 0;
  text[n] = '\0';
  char* end = nullptr;
  std::strtoull(text, &end, 10);
  return std::strtoull(end, nullptr, 10);
}

int openOwnSchedstat() { return open("/proc/thread-self/schedstat", O_RDONLY | O_CLOEXEC); }

}  // namespace

CoreContention::CoreContention(Waited waited) : hold_(kMinHold) {
  // SWARM_FORAGE_SHARE_JOBS=always: every job shared, for benchmarks of the threads' own cost.
  const char* env = std::getenv("SWARM_FORAGE_SHARE_JOBS");
  if (env && *env && std::string(env) != "always")
    throw std::invalid_argument(std::string("SWARM_FORAGE_SHARE_JOBS must be unset or 'always' (got '") +
                                env + "')");
  if (!waited && env && *env) waited = [] { return uint64_t{0}; };
  waited_ = waited ? std::move(waited) : [this] { return threadsWaited(); };
}

CoreContention::~CoreContention() {
  for (int fd : fds_)
    if (fd >= 0) close(fd);
}

void CoreContention::addThisThread() {
  const int fd = openOwnSchedstat();
  std::lock_guard<std::mutex> lock(mutex_);
  fds_.push_back(fd);
}

uint64_t CoreContention::threadsWaited() {
  const int own = openOwnSchedstat();  // whichever thread calls the jobs
  uint64_t total = runDelay(own);
  if (own >= 0) close(own);
  std::lock_guard<std::mutex> lock(mutex_);
  for (int fd : fds_) total += runDelay(fd);
  return total;
}

bool CoreContention::shareJob(unsigned threads) {
  const uint64_t job = jobs_.load(std::memory_order_relaxed) + 1;
  jobs_.store(job, std::memory_order_relaxed);
  if (job >= until_) {
    const uint64_t waited = waited_();
    const auto now = std::chrono::steady_clock::now();
    const double span = std::chrono::duration<double, std::nano>(now - last_time_).count() * threads;
    // Less than last time when another thread calls the jobs (its own run delay is read): not contention.
    const bool high =
        job > 1 && waited > last_waited_ && static_cast<double>(waited - last_waited_) >= kContended * span;
    if (solo_) {  // the hold is over: share a window, and read after it
      solo_ = false;
      probing_ = true;
      until_ = job + kWindow;
    } else if (high && (probing_ || strike_)) {  // two windows in a row: not a kernel thread's burst
      solo_ = true;
      strike_ = probing_ = false;
      until_ = job + hold_;
      hold_ = std::min(2 * hold_, kMaxHold);
    } else {
      strike_ = high;
      probing_ = false;
      if (!high) hold_ = kMinHold;
      until_ = job + kWindow;
    }
    last_waited_ = waited;
    last_time_ = now;
  }
  if (solo_) alone_.store(alone_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  return !solo_;
}

}  // namespace swarm_forage
