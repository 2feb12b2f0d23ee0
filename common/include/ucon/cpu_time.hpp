#pragma once
/// @file cpu_time.hpp
/// CPU time of the calling thread, for measuring a computation's own cost on a shared machine
/// (time other processes take the core away is not counted). Measurement only: no node
/// decides anything from it.
#include <time.h>

namespace ucon {

/// CPU seconds used by the calling thread so far (CLOCK_THREAD_CPUTIME_ID).
inline double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace ucon
