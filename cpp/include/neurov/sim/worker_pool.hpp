// Threads kept for the many short calls of a vector environment: a batch
// step of 256 lanes takes about half a millisecond, and starting and joining
// a std::thread at every call cost a tenth of that (bench/README.md). The
// workers wait on a condition variable between calls; run() hands each its
// share and takes share 0 itself.
//
// One run() at a time: a second caller (another Python thread, the GIL
// released) finds the pool busy and gets false back, to do the work some
// other way. A pool created before fork() has no workers in the child: the
// child's first run() finds the process changed and returns false too.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

namespace neurov {

class WorkerPool {
 public:
  /// A pool of `threads` - 1 workers besides the caller (0: one per
  /// hardware thread). Workers the system refuses are left out (size()
  /// says how many there are).
  explicit WorkerPool(unsigned threads = 0)
      : pid_(process_id()), workers_(std::make_unique<std::vector<std::thread>>()) {
    const unsigned n = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
    workers_->reserve(n - 1);
    try {
      for (unsigned t = 1; t < n; ++t) workers_->emplace_back([this, t] { work(t); });
    } catch (const std::system_error&) {
    }
  }

  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  ~WorkerPool() {
    if (process_id() != pid_) {
      // After fork() the workers and whoever held the mutexes live in the
      // parent: touching either here could hang, so the child leaves them.
      (void)workers_.release();
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    for (std::thread& w : *workers_) w.join();
  }

  /// Threads a run() can use: the workers and the caller.
  unsigned size() const noexcept { return static_cast<unsigned>(workers_->size()) + 1; }

  /// Calls share(t) for every t in [0, n), n <= size(), share 0 on the
  /// calling thread, and returns true once all have returned; returns false
  /// without calling anything when the pool is busy with another run() or
  /// was inherited through fork(). `share` must not throw.
  template <typename Share>
  bool run(unsigned n, Share& share) noexcept {
    if (n == 0) return true;
    if (n > size() || process_id() != pid_) return false;
    std::unique_lock<std::mutex> busy(run_mutex_, std::try_to_lock);
    if (!busy.owns_lock()) return false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      task_ = &share;
      call_ = [](void* s, unsigned t) noexcept { (*static_cast<Share*>(s))(t); };
      shares_ = n;
      remaining_ = n - 1;
      ++generation_;
    }
    if (n > 1) wake_.notify_all();
    share(0u);
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return remaining_ == 0; });
    task_ = nullptr;
    return true;
  }

 private:
  static long process_id() noexcept {
#if defined(__unix__) || defined(__APPLE__)
    return static_cast<long>(::getpid());
#else
    return 0;
#endif
  }

  void work(unsigned t) noexcept {
    std::size_t seen = 0;
    for (;;) {
      void* task;
      void (*call)(void*, unsigned) noexcept;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return stopping_ || generation_ != seen; });
        if (stopping_) return;
        seen = generation_;
        if (t >= shares_) continue;
        task = task_;
        call = call_;
      }
      call(task, t);
      bool last;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        last = --remaining_ == 0;
      }
      if (last) done_.notify_one();
    }
  }

  long pid_;
  std::unique_ptr<std::vector<std::thread>> workers_;
  std::mutex run_mutex_;  // one run() at a time
  std::mutex mutex_;      // guards what follows
  std::condition_variable wake_, done_;
  void* task_ = nullptr;
  void (*call_)(void*, unsigned) noexcept = nullptr;
  unsigned shares_ = 0, remaining_ = 0;
  std::size_t generation_ = 0;
  bool stopping_ = false;
};

}  // namespace neurov
