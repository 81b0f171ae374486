#include "swarm_forage/core/util/worker_pool.hpp"

#include <algorithm>
#include <chrono>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define SWARM_FORAGE_PAUSE() _mm_pause()
#else
#define SWARM_FORAGE_PAUSE() std::this_thread::yield()
#endif

namespace swarm_forage {

namespace {

// Waits until ready() for up to `spin`, first with pause (a job's last task is often microseconds away),
// then yielding the core; false when it is still not ready.
template <typename Ready>
bool spinUntil(Ready ready, std::chrono::microseconds spin) {
  const auto start = std::chrono::steady_clock::now();
  for (unsigned k = 0;; ++k) {
    if (ready()) return true;
    if ((k & 63) != 63) {
      SWARM_FORAGE_PAUSE();
      continue;
    }
    const auto waited = std::chrono::steady_clock::now() - start;
    if (waited >= spin) return false;
    if (waited >= spin / 8) std::this_thread::yield();
  }
}

// A simulation dispatches several jobs per tick: a thread that goes to sleep between them (or while a job
// ends) takes tens of microseconds to wake, more than many jobs last. Longer idle periods sleep.
constexpr std::chrono::microseconds kSpin{200};

}  // namespace

unsigned WorkerPool::cores() { return std::max(1u, std::thread::hardware_concurrency()); }

WorkerPool::WorkerPool(unsigned threads, CoreContention::Waited waited)
    : threads_(threads == 0 ? cores() : threads), contention_(std::move(waited)), shares_(threads_) {
  for (unsigned w = 1; w < threads_; ++w) workers_.emplace_back([this, w] { loop(w); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void WorkerPool::work(unsigned worker) {
  for (unsigned k = 0; k < threads_; ++k) {  // its own share first, then the others'
    Share& share = shares_[(worker + k) % threads_];
    for (std::size_t t = share.next.fetch_add(1); t < share.end; t = share.next.fetch_add(1)) {
      try {
        job_(t, worker);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!error_) error_ = std::current_exception();
      }
    }
  }
}

void WorkerPool::dispatch(std::size_t tasks, std::function<void(std::size_t, unsigned)> f) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = std::move(f);
    for (unsigned w = 0; w < threads_; ++w) {
      shares_[w].next.store(tasks * w / threads_, std::memory_order_relaxed);
      shares_[w].end = tasks * (w + 1) / threads_;
    }
    busy_.store(threads_ - 1, std::memory_order_relaxed);
    error_ = nullptr;
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();  // no system call while every worker still spins
  work(0);
  const auto idle = [this] { return busy_.load(std::memory_order_acquire) == 0; };
  if (!spinUntil(idle, kSpin)) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, idle);
  }
  std::lock_guard<std::mutex> lock(mutex_);  // the error and job are the workers' no longer
  job_ = nullptr;
  if (error_) std::rethrow_exception(error_);
}

void WorkerPool::loop(unsigned worker) {
  contention_.addThisThread();
  uint64_t seen = 0;
  for (;;) {
    spinUntil([&] { return generation_.load(std::memory_order_acquire) != seen; }, kSpin);
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_.load() != seen; });
      if (stop_) return;
      seen = generation_.load();
    }
    work(worker);
    if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      // Under the mutex: the dispatcher either sees busy_ == 0 or is already waiting when this notifies.
      std::lock_guard<std::mutex> lock(mutex_);
      done_.notify_one();
    }
  }
}

}  // namespace swarm_forage
