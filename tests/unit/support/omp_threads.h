// The caller's OpenMP thread count restored at the end of a scope, also when
// an assertion ends a test early (tests that run a simulation on one thread
// and on several).
#pragma once

#include <omp.h>

namespace vt::test {

struct RestoreThreads {
  int count = omp_get_max_threads();
  ~RestoreThreads() { omp_set_num_threads(count); }
};

}  // namespace vt::test
