#include "swarm_forage/core/util/worker_pool.hpp"

#include <algorithm>
#include <chrono>

namespace swarm_forage {

unsigned WorkerPool::cores() { return std::max(1u, std::thread::hardware_concurrency()); }

WorkerPool::WorkerPool(unsigned threads) : threads_(threads == 0 ? cores() : threads) {
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
  for (std::size_t t = next_.fetch_add(1); t < tasks_; t = next_.fetch_add(1)) {
    try {
      job_(t, worker);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
  }
}

void WorkerPool::dispatch(std::size_t tasks, std::function<void(std::size_t, unsigned)> f) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = std::move(f);
    tasks_ = tasks;
    next_ = 0;
    busy_ = threads_ - 1;
    error_ = nullptr;
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  work(0);
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return busy_ == 0; });
  job_ = nullptr;
  if (error_) std::rethrow_exception(error_);
}

void WorkerPool::loop(unsigned worker) {
  uint64_t seen = 0;
  for (;;) {
    // Spin for a moment first: a simulation dispatches several jobs per tick, and a sleeping thread takes
    // tens of microseconds to wake. Longer idle periods (other processes' turn in lockstep) sleep.
    const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(200);
    while (generation_.load(std::memory_order_acquire) == seen && std::chrono::steady_clock::now() < until)
      std::this_thread::yield();
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_.load() != seen; });
      if (stop_) return;
      seen = generation_.load();
    }
    work(worker);
    std::lock_guard<std::mutex> lock(mutex_);
    if (--busy_ == 0) done_.notify_one();
  }
}

}  // namespace swarm_forage
