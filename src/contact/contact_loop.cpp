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

ContactLoop::HeldPairSums::HeldPairSums(std::size_t bodies, std::vector<Vec3>& force,
                                        std::vector<double>* load)
    : force_(force), load_(load), count_(load ? bodies : 0, 0) {
  force_.assign(bodies, Vec3::Zero());
  if (load_) load_->assign(bodies, 0.0);
}

void ContactLoop::HeldPairSums::add(int i, int j, const Vec3& f) {
  force_[i] += f;
  force_[j] -= f;
  if (!load_) return;
  const double magnitude = f.norm();
  (*load_)[i] += magnitude;
  (*load_)[j] += magnitude;
  ++count_[i];
  ++count_[j];
}

void ContactLoop::HeldPairSums::finish() {
  for (std::size_t i = 0; i < count_.size(); ++i)
    if (count_[i]) (*load_)[i] /= count_[i];
}

}  // namespace granudrag
