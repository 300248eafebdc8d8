// The thread budget of the split factorisation (issue 33, item 7): one thread means one.
//  - run_halves, which runs SplitCholesky's two halves, keeps every OpenMP region a half opens
//    (CHOLMOD 3.0's supernodal factorisation opens regions of a fixed four threads) on the
//    half's thread, for a budget of one thread as for two. A one-thread OpenMP region around the
//    halves let those regions run four threads, created afresh for each supernode.
//  - On two threads the halves run side by side, on one thread one after the other on the
//    caller's thread; the caller's OpenMP setting is restored afterwards.
#include <gtest/gtest.h>
#include <omp.h>

#include <array>

#include "core/split_cholesky.hpp"

using namespace c2d::core;

namespace {

/// OpenMP's rule: a parallel region opened here runs on one thread whatever its num_threads
/// clause asks (CHOLMOD's ask for four) once the active levels reach max-active-levels. (A rule
/// read through the API, so the test needs no OpenMP compilation of its own.)
bool regions_opened_here_run_serially() {
  return omp_get_active_level() >= omp_get_max_active_levels();
}

}  // namespace

TEST(SplitThreads, RegionsInsideTheHalvesRunOnOneThreadForEveryBudget) {
  for (const int budget : {1, 2}) {
    std::array<bool, 2> serial{false, false};
    ASSERT_TRUE(run_halves(budget, [&](int h) {
      serial[h] = regions_opened_here_run_serially();
      return true;
    }));
    EXPECT_TRUE(serial[0]) << "budget " << budget;
    EXPECT_TRUE(serial[1]) << "budget " << budget;
  }
}

TEST(SplitThreads, OneThreadRunsTheHalvesOnTheCallersThreadTwoSideBySide) {
  std::array<int, 2> team{0, 0}, level{-1, -1};
  ASSERT_TRUE(run_halves(1, [&](int h) {
    team[h] = omp_get_num_threads();
    level[h] = omp_get_level();
    return true;
  }));
  EXPECT_EQ(team, (std::array<int, 2>{1, 1}));
  EXPECT_EQ(level, (std::array<int, 2>{0, 0}));  // no OpenMP region around the halves
  std::array<int, 2> thread{-1, -1};
  ASSERT_TRUE(run_halves(2, [&](int h) {
    team[h] = omp_get_num_threads();
    thread[h] = omp_get_thread_num();
    return true;
  }));
  if (omp_get_thread_limit() > 1) {  // (OMP_THREAD_LIMIT=1 leaves one thread for everything)
    EXPECT_EQ(team, (std::array<int, 2>{2, 2}));
    EXPECT_NE(thread[0], thread[1]);
  }
  EXPECT_FALSE(run_halves(1, [](int h) { return h == 0; }));
  EXPECT_FALSE(run_halves(2, [](int h) { return h == 1; }));
}

TEST(SplitThreads, TheCallersOpenMpSettingIsRestored) {
  const int before = omp_get_max_active_levels();
  ASSERT_TRUE(run_halves(1, [](int) { return true; }));
  ASSERT_TRUE(run_halves(2, [](int) { return true; }));
  EXPECT_EQ(omp_get_max_active_levels(), before);
}
