#pragma once
// CPU time of the calling thread (POSIX): jobs that run on several threads each report their
// own cost, which on a shared machine is fairer than the wall clock.
#include <time.h>

namespace dynweigh::granular {

inline double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

}  // namespace dynweigh::granular
