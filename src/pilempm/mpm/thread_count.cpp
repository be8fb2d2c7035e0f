#include "pilempm/mpm/thread_count.hpp"

#include <omp.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

namespace pilempm::mpm {

ThreadBudget current_thread_budget() {
  ThreadBudget budget;
  cpu_set_t mask;
  CPU_ZERO(&mask);
  budget.cores =
      sched_getaffinity(0, sizeof mask, &mask) == 0 ? CPU_COUNT(&mask) : omp_get_num_procs();
  // /proc/loadavg: "0.52 0.58 0.59 3/467 12345": the averages, then runnable/all tasks (the
  // runnable ones include this thread).
  long fewest = -1;
  for (int look = 0; look < 5; ++look) {
    if (look > 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    std::FILE* file = std::fopen("/proc/loadavg", "r");
    if (file == nullptr) break;
    double one = 0.0, five = 0.0, fifteen = 0.0;
    long runnable = 0, all = 0;
    const bool read =
        std::fscanf(file, "%lf %lf %lf %ld/%ld", &one, &five, &fifteen, &runnable, &all) == 5;
    std::fclose(file);
    if (!read) break;
    fewest = fewest < 0 ? runnable : std::min(fewest, runnable);
  }
  budget.load = static_cast<double>(std::max(0L, fewest - 1));
  budget.max_threads = omp_get_max_threads();
  return budget;
}

int default_thread_count(std::size_t particles, const ThreadBudget& budget) {
  // Busy cores: the load rounded to the nearest whole process.
  const long busy = std::lround(std::clamp(budget.load, 0.0, 1.0e6));
  const long idle = std::max(1L, static_cast<long>(budget.cores) - busy);
  const long by_size = std::max<long>(1, static_cast<long>(particles / kParticlesPerThread));
  return static_cast<int>(
      std::max(1L, std::min({static_cast<long>(budget.max_threads), idle, by_size})));
}

int default_thread_count(std::size_t particles) {
  return default_thread_count(particles, current_thread_budget());
}

}  // namespace pilempm::mpm
