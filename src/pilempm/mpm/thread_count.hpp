#pragma once
// The number of OpenMP threads a solver uses when the case does not say (threads = 0).
//
// Every parallel loop of a step ends at a barrier, so a run is as fast as its slowest thread: a
// thread whose core is taken by another busy process holds all others at every loop's end (the
// quick case ran 25 times slower beside one `yes > /dev/null` on 2 cores). The default therefore
// counts only the cores this process may run on (its affinity mask) that other processes do not
// keep busy: the runnable tasks of the machine (/proc/loadavg) besides this one, the fewest of
// five looks 2 ms apart, so that a short burst is not counted (the 1-minute load average is not
// used: it lags a minute behind, and it counts this process's own threads of a previous run), and
// it gives each thread at least kParticlesPerThread particles (the quick case, 1 558 particles,
// still runs 1.56 times faster on two threads than on one; tiny cases do not). The count is
// fixed when the solver is made: results are bitwise repeatable for a given count, which the run
// reports (set [solver] threads for the same count on every run).
#include <cstddef>

namespace pilempm::mpm {

/// Fewer particles than this per thread do not pay for the barriers.
inline constexpr std::size_t kParticlesPerThread = 500;

/// What the default is made of (for messages and tests).
struct ThreadBudget {
  int cores = 1;        ///< CPUs in this process's affinity mask
  double load = 0.0;    ///< cores kept busy by other processes now
  int max_threads = 1;  ///< omp_get_max_threads() (OMP_NUM_THREADS caps it)
};

/// The machine as it is now.
ThreadBudget current_thread_budget();

/// min(max_threads, cores not busy (at least 1), particles / kParticlesPerThread (at least 1)).
int default_thread_count(std::size_t particles, const ThreadBudget& budget);
/// The same for the machine as it is now.
int default_thread_count(std::size_t particles);

}  // namespace pilempm::mpm
