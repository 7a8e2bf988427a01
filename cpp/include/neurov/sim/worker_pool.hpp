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
  explicit WorkerPool(unsigned threads = 0) : pid_(process_id()), s_(std::make_unique<Shared>()) {
    const unsigned n = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
    s_->workers.reserve(n - 1);
    try {
      for (unsigned t = 1; t < n; ++t) s_->workers.emplace_back([s = s_.get(), t] { work(*s, t); });
    } catch (const std::system_error&) {
    }
  }

  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  ~WorkerPool() {
    if (process_id() != pid_) {
      // After fork() the workers, and the waits the mutexes and condition
      // variables record, belong to the parent: destroying them here could
      // hang (a condition variable's destructor waits for its waiters), so
      // the child leaves them.
      (void)s_.release();
      return;
    }
    {
      std::lock_guard<std::mutex> lock(s_->mutex);
      s_->stopping = true;
    }
    s_->wake.notify_all();
    for (std::thread& w : s_->workers) w.join();
  }

  /// Threads a run() can use: the workers and the caller.
  unsigned size() const noexcept { return static_cast<unsigned>(s_->workers.size()) + 1; }

  /// Calls share(t) for every t in [0, n), n <= size(), share 0 on the
  /// calling thread, and returns true once all have returned; returns false
  /// without calling anything when the pool is busy with another run() or
  /// was inherited through fork(). `share` must not throw.
  template <typename Share>
  bool run(unsigned n, Share& share) noexcept {
    if (n == 0) return true;
    if (n > size() || process_id() != pid_) return false;
    Shared& s = *s_;
    std::unique_lock<std::mutex> busy(s.run_mutex, std::try_to_lock);
    if (!busy.owns_lock()) return false;
    {
      std::lock_guard<std::mutex> lock(s.mutex);
      s.task = &share;
      s.call = [](void* f, unsigned t) noexcept { (*static_cast<Share*>(f))(t); };
      s.shares = n;
      s.remaining = n - 1;
      ++s.generation;
    }
    if (n > 1) s.wake.notify_all();
    share(0u);
    std::unique_lock<std::mutex> lock(s.mutex);
    s.done.wait(lock, [&s] { return s.remaining == 0; });
    s.task = nullptr;
    return true;
  }

 private:
  /// What the workers share, on the heap so that a forked child can leave it.
  struct Shared {
    std::vector<std::thread> workers;
    std::mutex run_mutex;  // one run() at a time
    std::mutex mutex;      // guards what follows
    std::condition_variable wake, done;
    void* task = nullptr;
    void (*call)(void*, unsigned) noexcept = nullptr;
    unsigned shares = 0, remaining = 0;
    std::size_t generation = 0;
    bool stopping = false;
  };

  static long process_id() noexcept {
#if defined(__unix__) || defined(__APPLE__)
    return static_cast<long>(::getpid());
#else
    return 0;
#endif
  }

  static void work(Shared& s, unsigned t) noexcept {
    std::size_t seen = 0;
    for (;;) {
      void* task;
      void (*call)(void*, unsigned) noexcept;
      {
        std::unique_lock<std::mutex> lock(s.mutex);
        s.wake.wait(lock, [&] { return s.stopping || s.generation != seen; });
        if (s.stopping) return;
        seen = s.generation;
        if (t >= s.shares) continue;
        task = s.task;
        call = s.call;
      }
      call(task, t);
      bool last;
      {
        std::lock_guard<std::mutex> lock(s.mutex);
        last = --s.remaining == 0;
      }
      if (last) s.done.notify_one();
    }
  }

  long pid_;
  std::unique_ptr<Shared> s_;
};

/// The pool every threaded batch step of the process shares (the bindings'
/// BatchSimulator.step and TrackingTask.step_batch), for a step on `threads`
/// threads: nullptr for one, which starts none; else one pool, built at its
/// first use with a thread per hardware thread and joined at exit.
inline WorkerPool* shared_pool(unsigned threads) {
  if (threads == 1) return nullptr;
  static WorkerPool pool;
  return &pool;
}

}  // namespace neurov
