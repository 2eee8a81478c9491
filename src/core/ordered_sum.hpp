#pragma once
// A parallel sum whose bits depend on the thread count only: each thread sums one contiguous
// range in index order, and the partial sums are added in thread order. (An OpenMP reduction
// combines them in whatever order the threads finish, so two runs could differ in the last bit.)
// One thread gives the serial sum exactly.
#include <omp.h>

#include <vector>

namespace granudrag {

// The sum over i in [0, n) of term(i); T needs T{} as zero and +=.
template <class T, class Term>
T ordered_sum(long n, Term term) {
  std::vector<T> partial(omp_get_max_threads(), T{});
  int threads = 1;
#pragma omp parallel
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    if (t == 0) threads = nt;
    T s{};
    for (long i = n * t / nt; i < n * (t + 1) / nt; ++i) s += term(i);
    partial[t] = s;
  }
  T total{};
  for (int t = 0; t < threads; ++t) total += partial[t];
  return total;
}

}  // namespace granudrag
