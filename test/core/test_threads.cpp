// Threads: the worker pool, the neighbour grid in both layouts, and bit-identical runs for 1, 2 and 3
// threads with every controller (world sensing, motion and the controllers all run on the pool).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "sharing_pool.hpp"
#include "swarm_forage/core/run/simulation.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/core/world/spatial_grid.hpp"

namespace swarm_forage {
namespace {

TEST(WorkerPool, RunsEveryTaskOnceAndRethrows) {
  for (unsigned threads : {1u, 2u, 3u}) {
    WorkerPool pool(threads);
    // Shares that do not divide evenly, fewer tasks than workers, and a share that is slow (its tasks
    // are taken by the others), twice each: every task once.
    for (std::size_t tasks : {2u, 7u, 1000u})
      for (int job = 0; job < 2; ++job) {
        std::vector<std::atomic<int>> runs(tasks);
        std::atomic<unsigned> max_worker{0};
        pool.run(runs.size(), [&](std::size_t t, unsigned w) {
          if (t == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
          ++runs[t];
          if (w > max_worker) max_worker = w;
        });
        for (auto& r : runs) EXPECT_EQ(r.load(), 1) << tasks << " tasks on " << threads << " threads";
        EXPECT_LT(max_worker.load(), threads);
      }
    EXPECT_THROW(pool.run(10,
                          [](std::size_t t, unsigned) {
                            if (t == 7) throw std::runtime_error("task 7");
                          }),
                 std::runtime_error);
    int after = 0;  // still usable after a failed job
    pool.run(1, [&](std::size_t, unsigned) { ++after; });
    EXPECT_EQ(after, 1);
  }
  EXPECT_GE(WorkerPool(0).threads(), 1u);
}

// While other processes take the cores from the pool's threads (they wait for a core much of the time),
// jobs run on the calling thread alone, for a hold that doubles while it lasts; once a window of shared
// jobs finds the cores free again, the jobs are shared again.
TEST(WorkerPool, RunsJobsAloneWhileTheCoresAreContended) {
  uint64_t waited = 0, per_reading = 0;  // nanoseconds the threads waited for a core, as the pool reads them
  WorkerPool pool(2, [&] { return waited += per_reading; });
  uint64_t off_caller = 0;  // tasks a worker other than the caller ran
  const auto job = [&] {
    pool.run(64, [&](std::size_t, unsigned w) {
      if (w != 0) ++off_caller;
    });
  };
  for (int k = 0; k < 100; ++k) job();  // idle: every job may be shared
  EXPECT_EQ(pool.jobs(), 100u);
  EXPECT_EQ(pool.jobsAlone(), 0u);

  per_reading = uint64_t{1} << 50;     // contended from now on: far longer than any window lasts
  for (int k = 0; k < 60; ++k) job();  // readings by the 129th job and the 161st: two windows in a row
  EXPECT_EQ(pool.jobsAlone(), 0u);
  job();  // the second reading: this job and the next 255 (the first hold) run alone
  const uint64_t before = off_caller;
  for (int k = 0; k < 255; ++k) job();
  EXPECT_EQ(off_caller, before) << "a job ran on a worker while the cores were contended";
  EXPECT_EQ(pool.jobsAlone(), 256u);
  for (int k = 0; k < 32 + 512; ++k) job();  // a shared window finds it still contended: a hold of 512
  EXPECT_EQ(pool.jobsAlone(), 256u + 512u);

  per_reading = 0;                          // the other processes are gone
  for (int k = 0; k < 32 + 64; ++k) job();  // the window after the hold finds the cores free
  EXPECT_EQ(pool.jobsAlone(), 256u + 512u);
  EXPECT_EQ(pool.jobs(), 100u + 60u + 256u + 32u + 512u + 32u + 64u);

  // A reading below the last (another thread calls the jobs, and its own run delay is read) is no contention.
  uint64_t falling = uint64_t{1} << 60;
  WorkerPool other_caller(2, [&] { return falling -= uint64_t{1} << 50; });
  for (int k = 0; k < 200; ++k) other_caller.run(64, [](std::size_t, unsigned) {});
  EXPECT_EQ(other_caller.jobsAlone(), 0u);

  // SWARM_FORAGE_SHARE_JOBS: "always" shares every job; any other value is refused, naming the variable.
  setenv("SWARM_FORAGE_SHARE_JOBS", "sometimes", 1);
  try {
    WorkerPool refused(2);
    ADD_FAILURE() << "SWARM_FORAGE_SHARE_JOBS=sometimes was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("SWARM_FORAGE_SHARE_JOBS must be unset or 'always'"),
              std::string::npos)
        << e.what();
  }
  setenv("SWARM_FORAGE_SHARE_JOBS", "always", 1);
  EXPECT_NO_THROW(WorkerPool(2));
  unsetenv("SWARM_FORAGE_SHARE_JOBS");

  WorkerPool one(1, [&] { return waited += uint64_t{1} << 50; });  // one thread: nothing to share or count
  one.run(64, [](std::size_t, unsigned) {});
  EXPECT_EQ(one.jobs(), 0u);
}

// Every layout (every cell laid out; occupied cells ordered by a bitmap; occupied cells sorted) orders the
// points by cell, then index, and finds exactly the points within one cell.
TEST(UniformGrid, NeighboursMatchBruteForceInEveryLayout) {
  std::mt19937 gen(3);
  // 400 points, 0.5 m cells: every cell laid out in 8 x 8 m (and in 8.25 x 8.25 m: 289 cells, so the running
  // sum's 8-cell groups leave one cell to the scalar loop), a bitmap in 200 x 200 m, a sort in 1000 x 1000 m
  for (const double size : {8.0, 8.25, 200.0, 1000.0}) {
    std::uniform_real_distribution<double> u(0, size);
    std::vector<double> xs(400), ys(400);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      xs[i] = u(gen);
      ys[i] = u(gen);
    }
    UniformGrid grid(size, size, 0.5);
    UniformGrid::Bands bands;  // of 3 rows: each band's sorted positions in index order
    bands.rows = 3;
    grid.build(xs.data(), ys.data(), xs.size(), nullptr, &bands);
    std::vector<uint32_t> expected(xs.size());
    std::iota(expected.begin(), expected.end(), 0u);
    std::stable_sort(expected.begin(), expected.end(),
                     [&](uint32_t a, uint32_t b) { return grid.cellOf(a) < grid.cellOf(b); });
    EXPECT_EQ(grid.order(), expected) << size;
    const auto bandOf = [&](uint32_t i) { return grid.cellOf(i) / grid.columns() / 3; };
    std::iota(expected.begin(), expected.end(), 0u);
    std::stable_sort(expected.begin(), expected.end(),
                     [&](uint32_t a, uint32_t b) { return bandOf(a) < bandOf(b); });
    for (uint32_t& i : expected) i = grid.rank()[i];
    EXPECT_EQ(bands.order, expected) << size;
    ASSERT_EQ(bands.start.size(), static_cast<std::size_t>(grid.rows() / 3 + 2));
    for (std::size_t b = 0; b + 1 < bands.start.size(); ++b)
      for (uint32_t k = bands.start[b]; k < bands.start[b + 1]; ++k) EXPECT_EQ(bandOf(grid.order()[k]), b);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      std::set<uint32_t> found;
      std::vector<uint32_t> by_point, by_run;  // neighbourRuns: the same points in the same order
      grid.forNeighbours(xs[i], ys[i], [&](uint32_t k) {
        found.insert(grid.order()[k]);
        by_point.push_back(k);
      });
      UniformGrid::Run runs[UniformGrid::kMaxRuns];
      const std::size_t n_runs = grid.neighbourRuns(grid.cellX(xs[i]), grid.cellY(ys[i]), runs);
      for (std::size_t r = 0; r < n_runs; ++r)
        for (uint32_t k = runs[r].begin; k < runs[r].end; ++k) by_run.push_back(k);
      EXPECT_EQ(by_point, by_run);
      for (std::size_t j = 0; j < xs.size(); ++j) {
        const double dx = xs[j] - xs[i], dy = ys[j] - ys[i];
        if (dx * dx + dy * dy < 0.25) {
          EXPECT_TRUE(found.count(static_cast<uint32_t>(j))) << i << " " << j;
        }
      }
    }
  }
}

// One grid built again and again, switching between the dense and the sparse layout (and with points left
// out), answers as a grid built afresh each time.
TEST(UniformGrid, RebuildsAcrossLayoutsAsAFreshGrid) {
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(0, 200.0);
  UniformGrid reused(200, 200, 0.5);  // 160,000 cells: dense from 9,997 points
  for (const std::size_t n : {400, 12000, 400, 12000, 12000, 30}) {
    std::vector<double> xs(n), ys(n);
    std::vector<uint8_t> present(n);
    for (std::size_t i = 0; i < n; ++i) {
      xs[i] = u(gen);
      ys[i] = u(gen);
      present[i] = i % 7 != 3;
    }
    UniformGrid fresh(200, 200, 0.5);
    fresh.build(xs.data(), ys.data(), n, present.data());
    reused.build(xs.data(), ys.data(), n, present.data());
    EXPECT_EQ(reused.order(), fresh.order()) << n;
    EXPECT_EQ(reused.placed(), fresh.placed()) << n;
    for (int cy = 0; cy < reused.rows(); cy += 7)
      for (int cx = 0; cx < reused.columns(); cx += 3) {
        std::vector<uint32_t> a, b;
        reused.forNeighbours(cx * 0.5 + 0.25, cy * 0.5 + 0.25, [&](uint32_t k) { a.push_back(k); });
        fresh.forNeighbours(cx * 0.5 + 0.25, cy * 0.5 + 0.25, [&](uint32_t k) { b.push_back(k); });
        ASSERT_EQ(a, b) << n << " cell " << cx << "," << cy;
      }
  }
}

std::vector<double> bodies(const World& w) {
  const RobotBodies& r = w.robots();
  std::vector<double> v(r.x);
  v.insert(v.end(), r.y.begin(), r.y.end());
  v.insert(v.end(), r.theta.begin(), r.theta.end());
  for (int32_t c : r.carried) v.push_back(c);
  return v;
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// 4,096 robots: every parallel path runs (sensing chunks, motion bands, controller parts).
TEST(Threads, RunsAreBitIdenticalForOneTwoAndThreeThreads) {
  for (const std::string kind : {"crw", "dpo", "gp_dpo"}) {
    WorldConfig c;
    c.arena.name = "64x32";
    c.arena.width = 64;
    c.arena.height = 32;
    c.arena.n_blocks = 200;
    c.n_robots = 4096;
    c.seed = 5;
    std::vector<std::unique_ptr<Simulation>> runs;
    for (unsigned threads : {1u, 2u, 3u})
      runs.push_back(std::make_unique<Simulation>(c, kind, ControllerConfigs{}, sharingPool(threads)));
    for (int t = 0; t < 400; ++t) {
      const double throttle = t < 200 ? 0.0 : 0.5;
      for (auto& s : runs) s->step(throttle);
      for (std::size_t k = 1; k < runs.size(); ++k) {
        Simulation &a = *runs[0], &b = *runs[k];
        ASSERT_TRUE(sameBits(bodies(a.world()), bodies(b.world()))) << kind << " tick " << t << " run " << k;
        ASSERT_TRUE(sameBits(a.sensors().obstacle_x, b.sensors().obstacle_x)) << kind << " tick " << t;
        ASSERT_TRUE(sameBits(a.sensors().los_block_id, b.sensors().los_block_id)) << kind << " tick " << t;
        ASSERT_TRUE(sameBits(a.commands().left, b.commands().left)) << kind << " tick " << t;
        ASSERT_TRUE(sameBits(a.commands().task, b.commands().task))
            << kind << " tick " << t;  // ParallelBatch
        ASSERT_TRUE(sameBits(a.status().state_counts, b.status().state_counts)) << kind << " tick " << t;
        ASSERT_EQ(a.world().delivered(), b.world().delivered());
      }
    }
    EXPECT_TRUE(runs[0]->world().overlapFree()) << kind;
  }
}

// With population dynamics (robots dying, being born, failing and rejoining every few ticks) a run stays
// bit-identical for 1, 2 and 3 threads: the events come from the counter-based RNG, not from the pool.
TEST(Threads, PopulationDynamicsRunsAreBitIdenticalForOneTwoAndThreeThreads) {
  for (const std::string kind : {"crw", "dpo", "gp_dpo"}) {
    WorldConfig c;
    c.n_robots = 2048;  // above 2 x World::kChunk: motion runs in parallel bands
    c.seed = 9;
    c.population.death = 0.05;
    c.population.birth = 0.05;
    c.population.malfunction = 0.2;
    c.population.repair = 0.1;
    std::vector<std::unique_ptr<Simulation>> runs;
    for (unsigned threads : {1u, 2u, 3u})
      runs.push_back(std::make_unique<Simulation>(c, kind, ControllerConfigs{}, sharingPool(threads)));
    uint32_t events = 0;
    for (int t = 0; t < 300; ++t) {
      for (auto& s : runs) s->step();
      const PopulationEvents& e = runs[0]->world().population().events();
      events +=
          static_cast<uint32_t>(e.deaths.size() + e.births.size() + e.malfunctions.size() + e.repairs.size());
      for (std::size_t k = 1; k < runs.size(); ++k) {
        Simulation &a = *runs[0], &b = *runs[k];
        ASSERT_TRUE(sameBits(bodies(a.world()), bodies(b.world()))) << kind << " tick " << t << " run " << k;
        ASSERT_TRUE(sameBits(a.sensors().active, b.sensors().active)) << kind << " tick " << t;
        ASSERT_TRUE(sameBits(a.commands().left, b.commands().left)) << kind << " tick " << t;
        ASSERT_TRUE(sameBits(a.status().state_counts, b.status().state_counts)) << kind << " tick " << t;
        ASSERT_EQ(a.world().delivered(), b.world().delivered());
      }
    }
    EXPECT_GT(events, 50u) << kind << ": the dynamics must act for the comparison to mean something";
    EXPECT_LT(runs[0]->world().population().events().active, c.n_robots) << kind;
    EXPECT_TRUE(runs[0]->world().overlapFree()) << kind;
  }
}

}  // namespace
}  // namespace swarm_forage
