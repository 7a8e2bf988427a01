// The worker pool (sim/worker_pool.hpp): every share of a run is called once,
// on its own thread, run after run; a busy pool refuses a second caller
// without calling anything; and a batch stepped through it gives step()'s
// lanes exactly.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <cmath>
#include <set>
#include <thread>
#include <memory>
#include <vector>

#if defined(__unix__)
#include <sys/wait.h>
#include <unistd.h>
#endif

#include "neurov/neurov.hpp"
#include "neurov/sim/batch.hpp"
#include "neurov/sim/worker_pool.hpp"
#include "noisy_run.hpp"

namespace {

using namespace neurov;

TEST(WorkerPool, EveryShareOnceOnItsOwnThreadRunAfterRun) {
  WorkerPool pool(3);
  ASSERT_GE(pool.size(), 1u);
  const unsigned n = pool.size();
  for (int run = 0; run < 500; ++run) {
    std::vector<int> calls(n, 0);
    std::vector<std::thread::id> ids(n);
    auto share = [&](unsigned t) noexcept {
      ++calls[t];
      ids[t] = std::this_thread::get_id();
    };
    ASSERT_TRUE(pool.run(n, share));
    for (unsigned t = 0; t < n; ++t) ASSERT_EQ(calls[t], 1) << "run " << run << " share " << t;
    EXPECT_EQ(ids[0], std::this_thread::get_id());  // share 0 is the caller's
    EXPECT_EQ(std::set<std::thread::id>(ids.begin(), ids.end()).size(), n);
  }
}

TEST(WorkerPool, FewerSharesThanThreadsAndNone) {
  WorkerPool pool(3);
  std::atomic<int> calls{0};
  auto share = [&](unsigned) noexcept { ++calls; };
  EXPECT_TRUE(pool.run(1u, share));
  EXPECT_EQ(calls.load(), 1);
  EXPECT_TRUE(pool.run(0u, share));
  EXPECT_EQ(calls.load(), 1);
  EXPECT_FALSE(pool.run(pool.size() + 1, share));  // more than it has: nothing called
  EXPECT_EQ(calls.load(), 1);
}

TEST(WorkerPool, ABusyPoolRefusesASecondCaller) {
  WorkerPool pool(2);
  std::atomic<bool> inside{false}, release{false};
  auto slow = [&](unsigned t) noexcept {
    if (t != 0) return;
    inside = true;
    while (!release) std::this_thread::yield();
  };
  std::thread first([&] { EXPECT_TRUE(pool.run(1u, slow)); });
  while (!inside) std::this_thread::yield();
  int calls = 0;
  auto other = [&](unsigned) noexcept { ++calls; };
  EXPECT_FALSE(pool.run(1u, other));
  EXPECT_EQ(calls, 0);
  release = true;
  first.join();
  EXPECT_TRUE(pool.run(1u, other));
  EXPECT_EQ(calls, 1);
}

#if defined(__unix__)
TEST(WorkerPool, AForkedChildIsRefusedAndLeavesWithoutHanging) {
  auto pool = std::make_unique<WorkerPool>(2);
  auto share = [](unsigned) noexcept {};
  ASSERT_TRUE(pool->run(pool->size(), share));
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    // The child has no workers: run() refuses, the destructor returns.
    const bool refused = !pool->run(1u, share);
    pool.reset();
    _exit(refused ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_TRUE(pool->run(pool->size(), share));  // the parent's pool still works
}
#endif

TEST(WorkerPool, ABatchSteppedThroughItIsStep) {
  const SimulationConfig<double> c = neurov_test::noisy_run(0, 0.0);
  // Two shares (a third of a block in the second).
  const std::size_t lanes = 2 * kMinLanesPerThread + 16;
  std::vector<Vehicle<double>> vehicles(lanes, Vehicle<double>(nerov_parameters<double>()));
  std::vector<SimulationConfig<double>> configs(lanes, c);
  for (std::size_t i = 0; i < configs.size(); ++i) configs[i].seed = i;
  BatchSimulator<double> pooled, plain;
  ASSERT_TRUE(BatchSimulator<double>::create(vehicles, configs, pooled).ok());
  ASSERT_TRUE(BatchSimulator<double>::create(vehicles, configs, plain).ok());
  WorkerPool pool(2);
  std::vector<double> tau(6 * lanes);
  std::vector<std::uint8_t> a(lanes), b(lanes);
  for (int k = 0; k < 10; ++k) {
    for (std::size_t i = 0; i < tau.size(); ++i) tau[i] = 10.0 * std::sin(0.1 * (i + 7 * k));
    step_threaded(pooled, 2, tau.data(), nullptr, a.data(), nullptr, &pool);
    plain.step(tau.data(), nullptr, b.data());
    ASSERT_EQ(a, b);
    for (std::size_t i = 0; i < lanes; ++i)
      for (int d = 0; d < 6; ++d) {
        ASSERT_EQ(pooled.lane(i).observation().eta(d), plain.lane(i).observation().eta(d));
        ASSERT_EQ(pooled.lane(i).observation().nu(d), plain.lane(i).observation().nu(d));
      }
  }
}

}  // namespace
