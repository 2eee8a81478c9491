#include "contact/contact_history.hpp"

namespace granudrag {

void ContactHistory::carry_over(const PairList& before, const PairList& after) {
  if (before.rows() != after.rows() || shear.size() != before.size()) {  // first build
    resize(after.size());
    return;
  }
  spare_shear_.resize(after.size());
  spare_touching_.resize(after.size());
  Vec3* new_shear = spare_shear_.data();
  std::uint8_t* new_touching = spare_touching_.data();
  const long rows = static_cast<long>(after.rows());
#pragma omp parallel for schedule(static)
  for (long r = 0; r < rows; ++r) {
    int a = before.begin(r);
    const int a_end = before.end(r);
    for (int b = after.begin(r); b < after.end(r); ++b) {
      while (a < a_end && before.partner[a] < after.partner[b]) ++a;  // both rows are sorted
      const bool kept = a < a_end && before.partner[a] == after.partner[b];
      new_shear[b] = kept ? shear[a] : Vec3::Zero();
      new_touching[b] = kept ? touching[a] : 0;
    }
  }
  shear.swap(spare_shear_);
  touching.swap(spare_touching_);
}

}  // namespace granudrag
