#include "contact/contact_history.hpp"

namespace granudrag {

void ContactHistory::carry_over(const PairList& before, const PairList& after) {
  std::vector<Vec3> new_shear(after.size(), Vec3::Zero());
  std::vector<std::uint8_t> new_touching(after.size(), 0);
  if (before.rows() != after.rows() || shear.size() != before.size()) {  // first build
    shear.swap(new_shear);
    touching.swap(new_touching);
    return;
  }
  const long rows = static_cast<long>(after.rows());
#pragma omp parallel for schedule(static)
  for (long r = 0; r < rows; ++r) {
    int a = before.begin(r);
    const int a_end = before.end(r);
    for (int b = after.begin(r); b < after.end(r); ++b) {
      while (a < a_end && before.partner[a] < after.partner[b]) ++a;  // both rows are sorted
      if (a < a_end && before.partner[a] == after.partner[b]) {
        new_shear[b] = shear[a];
        new_touching[b] = touching[a];
      }
    }
  }
  shear.swap(new_shear);
  touching.swap(new_touching);
}

}  // namespace granudrag
