// The default thread count: the cores not busy with other processes, at most one thread per
// kParticlesPerThread particles, never more than OMP_NUM_THREADS allows, never less than one.
#include <gtest/gtest.h>

#include "pilempm/mpm/thread_count.hpp"

namespace pilempm::mpm {
namespace {

TEST(DefaultThreadCount, LeavesBusyCoresAlone) {
  const std::size_t large = 100 * kParticlesPerThread;
  EXPECT_EQ(default_thread_count(large, {2, 0.0, 2}), 2);
  EXPECT_EQ(default_thread_count(large, {2, 0.4, 2}), 2);  // a short burst of another process
  EXPECT_EQ(default_thread_count(large, {2, 1.0, 2}), 1);  // one `yes > /dev/null` beside it
  EXPECT_EQ(default_thread_count(large, {2, 2.0, 2}), 1);
  EXPECT_EQ(default_thread_count(large, {2, 16.0, 2}), 1);
  EXPECT_EQ(default_thread_count(large, {16, 3.6, 16}), 12);
}

TEST(DefaultThreadCount, SmallCasesRunOnFewerThreads) {
  const ThreadBudget idle_machine{16, 0.0, 16};
  EXPECT_EQ(default_thread_count(0, idle_machine), 1);
  EXPECT_EQ(default_thread_count(kParticlesPerThread - 1, idle_machine), 1);
  EXPECT_EQ(default_thread_count(3 * kParticlesPerThread, idle_machine), 3);
}

TEST(DefaultThreadCount, OmpNumThreadsCapsIt) {
  EXPECT_EQ(default_thread_count(100 * kParticlesPerThread, {16, 0.0, 4}), 4);
  EXPECT_EQ(default_thread_count(100 * kParticlesPerThread, {16, 0.0, 1}), 1);
}

TEST(DefaultThreadCount, TheMachineGivesAtLeastOneThread) {
  const ThreadBudget now = current_thread_budget();
  EXPECT_GE(now.cores, 1);
  EXPECT_GE(now.max_threads, 1);
  EXPECT_GE(now.load, 0.0);
  EXPECT_GE(default_thread_count(1000000), 1);
  EXPECT_LE(default_thread_count(1000000), now.cores);
}

}  // namespace
}  // namespace pilempm::mpm
