// VerletContacts' passes that read the contacts without changing them: the run guard's and the
// observables' checks (energy, overlap, coordination numbers), and for the active region the
// forces between held grains and which held grains have a partner awake.
#include <omp.h>

#include <algorithm>
#include <vector>

#include "contact/contact_law.hpp"
#include "contact/pair_geometry.hpp"
#include "contact/verlet_contacts.hpp"
#include "core/ordered_sum.hpp"

namespace granudrag {

// The checks below run every sample interval (the run guard, the coordination numbers): in
// parallel over the rows, or on a study's interval of 40 steps they cost 7 % of a 2-thread pull.
// With bodies held, they scan the pairs the step computes and add the held pairs' part, taken
// once per held set and list (for_held_touching_pairs): exact for the overlap and the counts;
// the energy's terms are summed in another order than without the region (its last bits differ).
double VerletContacts::elastic_energy(const Particles& p, const Box& box, const ContactParams& c) const {
  auto pair_energy = [&](int i, int j) {
    ContactGeometry g;
    return pair_geometry(p, box, i, j, g) ? hertz_normal_energy(c.kn, g.reff, g.contact_distance - g.r) : 0.0;
  };
  const PairList& pairs = list_.grain_pairs();
  double energy = ordered_sum<double>(checked_rows(), [&](long k) {
    double row = 0.0;
    for_computed_entries(k,
                         [&](long i, int e) { row += pair_energy(static_cast<int>(i), pairs.partner[e]); });
    return row;
  });
  if (!row_mode_.empty()) energy += held_pairs_energy(p, box, c);
  const PairList& intruders = list_.intruder_pairs();
  for (std::size_t b = 0; b < intruders.rows(); ++b)
    for (int e = intruders.begin(b); e < intruders.end(b); ++e)
      energy += pair_energy(list_.intruder_bodies()[b], intruders.partner[e]);
  return energy;
}

// The touching pairs of two held bodies, row by row (rows whose body is awake have none): the
// pairs whose part the checks keep between changes of the held set or of the lists.
template <class Visit>
void VerletContacts::for_held_touching_pairs(Visit&& visit) const {
  const PairList& pairs = list_.grain_pairs();
  for (std::size_t i = 0; i < pairs.rows(); ++i) {
    if (row_mode_[i] == kAll) continue;
    for (int e = pairs.begin(i); e < pairs.end(i); ++e)
      if ((*held_)[pairs.partner[e]] && grain_history_.touching[e])
        visit(static_cast<int>(i), pairs.partner[e]);
  }
}

const std::vector<int>& VerletContacts::held_pair_contacts() const {
  HeldPairs& h = held_pairs_;
  if (h.counted) return h.contacts;
  h.contacts.assign(list_.grain_pairs().rows(), 0);
  for_held_touching_pairs([&](int i, int j) {
    ++h.contacts[i];
    ++h.contacts[j];
  });
  h.counted = true;
  return h.contacts;
}

double VerletContacts::held_pairs_overlap(const Particles& p, const Box& box) const {
  HeldPairs& h = held_pairs_;
  if (h.overlapped) return h.overlap;
  h.overlap = 0;
  for_held_touching_pairs([&](int i, int j) {
    h.overlap = std::max(h.overlap, p.radius[i] + p.radius[j] - box.min_image(p.x[i] - p.x[j]).norm());
  });
  h.overlapped = true;
  return h.overlap;
}

double VerletContacts::held_pairs_energy(const Particles& p, const Box& box, const ContactParams& c) const {
  HeldPairs& h = held_pairs_;
  if (h.energized) return h.energy;
  h.energy = 0;  // serial, in row order: the same bits for any thread count
  for_held_touching_pairs([&](int i, int j) {
    ContactGeometry g;
    if (pair_geometry(p, box, i, j, g))
      h.energy += hertz_normal_energy(c.kn, g.reff, g.contact_distance - g.r);
  });
  h.energized = true;
  return h.energy;
}

int VerletContacts::contacts_of(int body) const {
  const PairList& intruders = list_.intruder_pairs();
  const std::vector<int>& bodies = list_.intruder_bodies();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (bodies[b] != body) continue;
    int n = 0;
    for (int e = intruders.begin(b); e < intruders.end(b); ++e) n += intruder_history_.touching[e];
    return n;
  }
  return 0;
}

void VerletContacts::new_contacts_of(int body, std::vector<int>& grains) const {
  grains.clear();
  const PairList& intruders = list_.intruder_pairs();
  const std::vector<int>& bodies = list_.intruder_bodies();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (bodies[b] != body) continue;
    for (int e = intruders.begin(b); e < intruders.end(b); ++e)
      if (intruder_new_[e]) grains.push_back(intruders.partner[e]);
  }
}

void VerletContacts::touching_contacts_of(int body, std::vector<int>& grains) const {
  grains.clear();
  const PairList& intruders = list_.intruder_pairs();
  const std::vector<int>& bodies = list_.intruder_bodies();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (bodies[b] != body) continue;
    for (int e = intruders.begin(b); e < intruders.end(b); ++e)
      if (intruder_history_.touching[e]) grains.push_back(intruders.partner[e]);
  }
}

void VerletContacts::count_contacts(std::vector<int>& contacts) const {
  // A row's partners belong to other threads' rows: threads past the first count into private
  // arrays, added afterwards (integers: the same result in any order). Atomic increments instead
  // made one thread slower than the serial pass.
  const PairList& pairs = list_.grain_pairs();
  if (!row_mode_.empty()) {
    const std::vector<int>& held = held_pair_contacts();
    for (std::size_t k = 0; k < held.size(); ++k) contacts[k] += held[k];
  }
  const long rows = checked_rows(), n = static_cast<long>(contacts.size());
  std::vector<std::vector<int>> extra(omp_get_max_threads());
#pragma omp parallel
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    if (t > 0) extra[t].assign(n, 0);
    int* count = t == 0 ? contacts.data() : extra[t].data();
    for (long k = rows * t / nt; k < rows * (t + 1) / nt; ++k)
      for_computed_entries(k, [&](long i, int e) {
        if (!grain_history_.touching[e]) return;
        ++count[i];
        ++count[pairs.partner[e]];
      });
#pragma omp barrier
    if (nt > 1) {
#pragma omp for schedule(static)
      for (long k = 0; k < n; ++k)
        for (int s = 1; s < nt; ++s) contacts[k] += extra[s][k];
    }
  }
  const PairList& intruders = list_.intruder_pairs();
  for (std::size_t b = 0; b < intruders.rows(); ++b)
    for (int e = intruders.begin(b); e < intruders.end(b); ++e)
      if (intruder_history_.touching[e]) {
        ++contacts[list_.intruder_bodies()[b]];
        ++contacts[intruders.partner[e]];
      }
}

void VerletContacts::held_pair_forces(const Particles& p, const Box& box, const ContactParams& c,
                                      std::vector<Vec3>& force, std::vector<double>* load) const {
  HeldPairSums sums(p.size(), force, load);
  if (!held_) return;
  const PairList& pairs = list_.grain_pairs();
  for (std::size_t i = 0; i < pairs.rows(); ++i) {
    if (!(*held_)[i]) continue;
    for (int e = pairs.begin(i); e < pairs.end(i); ++e) {
      const int j = pairs.partner[e];
      ContactGeometry g;
      if (!(*held_)[j] || !grain_history_.touching[e] || !pair_geometry(p, box, static_cast<int>(i), j, g))
        continue;
      Vec3 shear = grain_history_.shear[e];
      sums.add(static_cast<int>(i), j, hertz_history(c, g, 0.0, shear, false).force);
    }
  }
  sums.finish();
}

// The largest overlap over the lists' pairs: those touching at the last evaluation, or all.
double VerletContacts::largest_overlap(const Particles& p, const Box& box, bool touching_only) const {
  auto overlap = [&](int i, int j) {
    return p.radius[i] + p.radius[j] - box.min_image(p.x[i] - p.x[j]).norm();
  };
  const PairList& pairs = list_.grain_pairs();
  const long rows = static_cast<long>(pairs.rows());
  // The held pairs' part is taken apart for touching pairs only (held pairs out of touch keep
  // their distance too, but a bed's deepest overlap is asked before any step, held or not).
  const bool split = touching_only && !row_mode_.empty();
  double worst = split ? held_pairs_overlap(p, box) : 0.0;  // the largest is the same whatever the order
  if (split) {
#pragma omp parallel for schedule(static) reduction(max : worst)
    for (long k = 0; k < checked_rows(); ++k)
      for_computed_entries(k, [&](long i, int e) {
        if (grain_history_.touching[e])
          worst = std::max(worst, overlap(static_cast<int>(i), pairs.partner[e]));
      });
  } else {
#pragma omp parallel for schedule(static) reduction(max : worst)
    for (long i = 0; i < rows; ++i)
      for (int e = pairs.begin(i); e < pairs.end(i); ++e)
        if (!touching_only || grain_history_.touching[e])
          worst = std::max(worst, overlap(static_cast<int>(i), pairs.partner[e]));
  }
  const PairList& intruders = list_.intruder_pairs();
  for (std::size_t b = 0; b < intruders.rows(); ++b)
    for (int e = intruders.begin(b); e < intruders.end(b); ++e)
      if (!touching_only || intruder_history_.touching[e])
        worst = std::max(worst, overlap(list_.intruder_bodies()[b], intruders.partner[e]));
  return worst;
}

double VerletContacts::max_overlap(const Particles& p, const Box& box) const {
  return largest_overlap(p, box, true);
}

double VerletContacts::deepest_overlap(const Particles& p, const Box& box) const {
  return largest_overlap(p, box, false);
}

long VerletContacts::contact_count() const {
  long n = 0;
  for (auto t : grain_history_.touching) n += t;
  for (auto t : intruder_history_.touching) n += t;
  return n;
}

void VerletContacts::mark_exposed(std::vector<std::uint8_t>& exposed) const {
  if (!held_) {
    ContactLoop::mark_exposed(exposed);
    return;
  }
  // Serial: two rows may mark one body. Run at checks and list builds only.
  const std::uint8_t* held = held_->data();
  const PairList& pairs = list_.grain_pairs();
  for (std::size_t i = 0; i < pairs.rows(); ++i)
    for (int e = pairs.begin(i); e < pairs.end(i); ++e) {
      const int j = pairs.partner[e];
      if (held[i] != held[j]) exposed[i] = exposed[j] = 1;
    }
  const PairList& intruder = list_.intruder_pairs();
  for (int j : intruder.partner) exposed[j] = 1;
}

}  // namespace granudrag
