#include "contact/contact_loop.hpp"

#include <omp.h>

namespace granudrag {

void ContactLoop::accumulate(Particles& p, const Box& box, const ContactParams& c, double dt,
                             bool update_history) {
  prepare_accumulate();
  const long n = static_cast<long>(p.size());
#pragma omp parallel
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    accumulate_in_team(p, box, c, dt, update_history);
#pragma omp barrier
    finish_accumulate(p, n * t / nt, n * (t + 1) / nt);
  }
}

}  // namespace granudrag
