#include "contact/verlet_contacts.hpp"

#include <omp.h>

#include <algorithm>
#include <climits>
#include <memory>
#include <type_traits>

#include "contact/contact_batch.hpp"
#include "contact/contact_law.hpp"
#include "contact/pair_geometry.hpp"
#include "core/balanced_split.hpp"
#include "core/ordered_sum.hpp"

namespace granudrag {

bool VerletContacts::update_lists(Particles& p, const Box& box, Timers* timers, double max_drift_sq) {
  if (!list_.rebuild_due(p.size(), max_drift_sq)) return false;
  list_.build(p, box);
  if (timers) timers->stamp(Phase::Neighbor);
  after_build();
  if (timers) timers->stamp(Phase::History);
  return true;
}

void VerletContacts::rebuild(Particles& p, const Box& box) {
  list_.build(p, box);
  after_build();
}

void VerletContacts::after_build() {
  grain_history_.carry_over(list_.previous_grain_pairs(), list_.grain_pairs());
  intruder_history_.carry_over(list_.previous_intruder_pairs(), list_.intruder_pairs());
  intruder_force_.assign(list_.intruder_pairs().size(), Vec3::Zero());
  intruder_torque_.assign(list_.intruder_pairs().size(), Vec3::Zero());
  intruder_new_.assign(list_.intruder_pairs().size(), 0);
  classify_rows();
  balance_rows(omp_get_max_threads());
}

void VerletContacts::held_changed() {
  classify_rows();
  if (!row_split_.empty()) balance_rows(omp_get_max_threads());
}

void VerletContacts::classify_rows() {
  forget_held_pairs();
  const PairList& pairs = list_.grain_pairs();
  if (!held_ || held_->size() != pairs.rows()) {
    row_mode_.clear();
    scanned_rows_.clear();
    awake_start_.clear();
    awake_entries_.clear();
    return;
  }
  const std::uint8_t* held = held_->data();
  const long n = static_cast<long>(pairs.rows());
  row_mode_.resize(n);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    std::uint8_t mode = kAll;
    if (held[i]) {
      mode = kSkip;
      for (int e = pairs.begin(i); e < pairs.end(i) && mode == kSkip; ++e)
        if (!held[pairs.partner[e]]) mode = kAwakePartners;
    }
    row_mode_[i] = mode;
  }
  // The rows the step scans, in order, and the entries of held ones with an awake partner.
  scanned_rows_.clear();
  awake_start_.assign(1, 0);
  awake_entries_.clear();
  for (long i = 0; i < n; ++i) {
    if (row_mode_[i] == kSkip) continue;
    scanned_rows_.push_back(static_cast<int>(i));
    if (row_mode_[i] == kAwakePartners)
      for (int e = pairs.begin(i); e < pairs.end(i); ++e)
        if (!held[pairs.partner[e]]) awake_entries_.push_back(e);
    awake_start_.push_back(static_cast<int>(awake_entries_.size()));
  }
}

void VerletContacts::balance_rows(int threads) {
  // With the batched law a touching pair costs about two near misses (the scan, then the
  // gather, law and scatter); weights 1, 2 and 4 measured on a 7.7k pull with 2 threads: the
  // force loop took 0.55, 0.57 and 0.57 s.
  constexpr long kTouchWeight = 1;
  const PairList& pairs = list_.grain_pairs();
  const long n = static_cast<long>(pairs.rows());
  const std::uint8_t* touching = grain_history_.touching.data();
  // The cost of what scan_rows visits (for_computed_entries: with bodies held, nothing of a
  // skipped row and a held row's awake partners only): counted as whole rows, in a mostly
  // sleeping 70k bed one thread's even block took 8.0 s where the other's took 4.2, and the
  // threads waited for each other a sixth of the contact loop.
  std::vector<long> cost(n + 1, 0);
  const long rows = checked_rows();
#pragma omp parallel for schedule(static)
  for (long k = 0; k < rows; ++k) {
    long c = 1;
    for_computed_entries(k, [&](long, int e) { c += 1 + kTouchWeight * touching[e]; });
    cost[checked_row(k) + 1] = c;
  }
  for (long i = 0; i < n; ++i) cost[i + 1] += cost[i];
  // Two blocks of rows per thread, of equal cost: thread t runs blocks 2t and 2t + 1.
  const int blocks = 2 * threads;
  balanced_split(cost, blocks, row_split_);
  // The blocks can be run in two colours, even blocks together and then odd ones, writing
  // straight into the particles' forces, when no two blocks of one colour write the same body.
  // Block b writes its rows and their partners (j > i): those short of the block but one
  // (b + 2), and those beyond it, the excursions. Bodies ordered by a sweep (a pour's order,
  // core/spatial_order.hpp) have partners within a layer of their row, and excursions only
  // across a periodic sweep's boundary: rows of the first blocks reaching into the last one. A
  // bed in another order (imported) takes private arrays.
  colored_ = threads > 1 && colour_blocks_apart(pairs, row_split_);
  private_reach_.clear();
  if (threads == 1 || colored_) return;
  // Thread t runs blocks 2t and 2t + 1; what lies beyond the next thread's rows is an excursion.
  for (int t = 0; t < threads; ++t) {
    const long i0 = row_split_[2 * t], i1 = row_split_[2 * t + 2];
    const WriteReach w = write_reach(pairs, i0, i1, row_split_[std::min(2 * t + 4, blocks)]);
    std::array<BodyRange, 2> r{BodyRange{i0, std::max(i1, w.near_end + 1)}, BodyRange{}};
    if (w.far_last >= 0) r[1] = {w.far_first, w.far_last + 1};
    private_reach_.push_back(r);
  }
}

std::array<VerletContacts::BodyRange, 2> VerletContacts::private_ranges(int t, int nt, long n) const {
  if (nt == planned_threads_ && static_cast<int>(private_reach_.size()) == nt) return private_reach_[t];
  // A smaller team than planned takes whole blocks: from its first row on, all it may write.
  const long blocks = static_cast<long>(row_split_.size()) - 1;
  return {BodyRange{row_split_[blocks * t / nt], n}, BodyRange{}};
}

long VerletContacts::private_span() const {
  long span = 0;
  for (std::size_t t = 1; t < private_reach_.size(); ++t)
    for (const BodyRange& r : private_reach_[t]) span += r.last - r.first;
  return span;
}

WriteReach write_reach(const PairList& pairs, long i0, long i1, long limit) {
  WriteReach w{i1 - 1, LONG_MAX, -1};
  for (long r = i0; r < i1; ++r) {
    if (pairs.end(r) == pairs.begin(r)) continue;
    const int* first = pairs.partner.data() + pairs.begin(r);
    const int* last = pairs.partner.data() + pairs.end(r);
    if (last[-1] < limit) {  // rows are sorted: no excursion
      w.near_end = std::max<long>(w.near_end, last[-1]);
      continue;
    }
    const int* far = std::lower_bound(first, last, limit);
    if (far > first) w.near_end = std::max<long>(w.near_end, far[-1]);
    w.far_first = std::min<long>(w.far_first, *far);
    w.far_last = std::max<long>(w.far_last, last[-1]);
  }
  return w;
}

bool colour_blocks_apart(const PairList& pairs, const std::vector<long>& split) {
  // Per block: the largest partner short of the block but one, and the hull of the excursions.
  const int blocks = static_cast<int>(split.size()) - 1;
  std::vector<WriteReach> w(blocks);
  for (int b = 0; b < blocks; ++b)
    w[b] = write_reach(pairs, split[b], split[b + 1], split[std::min(b + 2, blocks)]);
  // Two blocks of one colour, b < c (so c >= b + 2): b's near part ends before c starts, and
  // c's parts lie beyond it. What can meet is an excursion of either block: each block's are
  // checked against the near part and the excursions of every other block of its colour.
  for (int b = 0; b < blocks; ++b) {
    if (w[b].far_last < 0) continue;
    for (int c = b % 2; c < blocks; c += 2) {
      if (c == b) continue;
      const bool meets_near = w[b].far_first <= w[c].near_end && split[c] <= w[b].far_last;
      const bool meets_far =
          w[c].far_last >= 0 && w[b].far_first <= w[c].far_last && w[c].far_first <= w[b].far_last;
      if (meets_near || meets_far) return false;
    }
  }
  return true;
}

void VerletContacts::evaluate_batch(const Particles& p, const ContactParams& c, double dt,
                                    bool update_history, ContactBatch& b, Vec3* f, Vec3* tq) {
  const double* radius = p.radius.data();
  const double* mass = p.mass.data();
  const Species* species = p.species.data();
  const Vec3* v = p.v.data();
  const Vec3* omega = p.omega.data();
  Vec3* shear = grain_history_.shear.data();
  const int n = b.size;
  for (int k = 0; k < n; ++k) {
    const int i = b.i[k], j = b.j[k];
    b.reff[k] = radius[i] * radius[j] / b.radsum[k];
    b.meff[k] = effective_mass(mass[i], species[i], mass[j], species[j]);
    const Vec3 vij = v[i] - v[j];
    const Vec3 w = radius[i] * omega[i] + radius[j] * omega[j];
    const Vec3& s = shear[b.entry[k]];
    b.vx[k] = vij.x(), b.vy[k] = vij.y(), b.vz[k] = vij.z();
    b.wx[k] = w.x(), b.wy[k] = w.y(), b.wz[k] = w.z();
    b.sx[k] = s.x(), b.sy[k] = s.y(), b.sz[k] = s.z();
  }
  hertz_history_batch(c, dt, update_history, b, simd_);
  for (int k = 0; k < n; ++k) {
    const int i = b.i[k], j = b.j[k];
    const Vec3 force(b.fx[k], b.fy[k], b.fz[k]), torque(b.tx[k], b.ty[k], b.tz[k]);
    f[i] += force;
    tq[i] -= radius[i] * torque;
    f[j] -= force;
    tq[j] -= radius[j] * torque;
    shear[b.entry[k]] = Vec3(b.sx[k], b.sy[k], b.sz[k]);
  }
  b.size = 0;
}

void VerletContacts::scan_rows(const Particles& p, const Box& box, const ContactParams& c, double dt,
                               bool update_history, long i0, long i1, ContactBatch& b, Vec3* f, Vec3* tq) {
  // Touching pairs are collected branch-free into the batch and evaluated together. Raw
  // pointers and a local count: through the containers the compiler reloads them every entry.
  // The box and the list's offsets are copied into locals too: the batch's stores could alias
  // them for all the compiler knows, and it reloaded them every entry.
  const PairList& pairs = list_.grain_pairs();
  const Vec3* x = p.x.data();
  const double* radius = p.radius.data();
  const int* partner = pairs.partner.data();
  const int* offset = pairs.offset.data();
  const std::uint8_t* wrapping = list_.wrapping_rows().data();
  const double lx = box.lx, ly = box.ly;
  const std::uint8_t* mode = row_mode_.empty() ? nullptr : row_mode_.data();
  std::uint8_t* touching = grain_history_.touching.data();
  Vec3* shear = grain_history_.shear.data();
  int size = 0;
  // One row's entries, first .. last - 1, or with `listed` the entries listed there in
  // awake_entries_ (a held row's awake partners: its pairs with held partners are left as they
  // are). `periodic`: its partners may lie across a boundary. Most rows have none, and skip the
  // minimum image's compares and jumps (a fifth of the scan's instructions).
  const int* listed_entry = awake_entries_.data();
  // Prefetches, because in a bed larger than the cache the scan waited on memory: a 70k bed's
  // step reads about 23 MB, and its force loop took 1.5x a 7.7k bed's time per pair for the
  // same instructions and the same misses counted beyond a 1 MiB L2 (benchmark.md, 2026-11-29).
  // Two streams are not met in time by the hardware's prefetchers: a row's partner with the
  // largest index, in the next layer of the sweep, first read at this step by this row (its
  // position, velocities, radius, mass, and the force and torque it receives), and the springs
  // the batch updates a few hundred entries after the scan has passed them. Fetching the first
  // rows ahead and the second as the scan passes made the 70k pull 1.3x faster and the 7.7k
  // one at most 3 % slower.
  constexpr long kRowsAhead = 16;  // 8 and 32 measured alike
  const Vec3* v = p.v.data();
  const Vec3* omega = p.omega.data();
  const double* mass = p.mass.data();
  // always_inline: GCC takes a function that only prefetches for one without effects, and
  // dropped the calls before it would have inlined them.
  auto prefetch_far_partner = [=] [[gnu::always_inline]] (long row) {
    if (offset[row + 1] == offset[row]) return;
    const int j = partner[offset[row + 1] - 1];
    __builtin_prefetch(&x[j]);
    __builtin_prefetch(&v[j]);
    __builtin_prefetch(&omega[j]);
    __builtin_prefetch(&radius[j]);
    __builtin_prefetch(&mass[j]);
    __builtin_prefetch(&f[j], 1);
    __builtin_prefetch(&tq[j], 1);
  };
  auto scan_row = [&](long i, int first, int last, auto periodic, auto listed) {
    // Plain doubles rather than Vec3 here: Eigen packs x, y into one register and z into
    // another, and the shuffles and spills cost more than the arithmetic.
    const double xi = x[i].x(), yi = x[i].y(), zi = x[i].z();
    const double ri = radius[i];
    for (int k = first; k < last; ++k) {
      int e = k;
      if constexpr (listed) e = listed_entry[k];
      const int j = partner[e];
      __builtin_prefetch(&shear[e], 1);
      double dx = xi - x[j].x(), dy = yi - x[j].y();
      if constexpr (periodic) {
        dx = Box::min_image(dx, lx);
        dy = Box::min_image(dy, ly);
      }
      const double dz = zi - x[j].z();
      const double rsq = dx * dx + dy * dy + dz * dz;
      const double radsum = ri + radius[j];
      const std::uint8_t touches = rsq < radsum * radsum;
      b.dx[size] = dx;
      b.dy[size] = dy;
      b.dz[size] = dz;
      b.rsq[size] = rsq;
      b.radsum[size] = radsum;
      b.i[size] = static_cast<int>(i);
      b.j[size] = j;
      b.entry[size] = e;
      size += touches;
      if (touching[e] > touches) shear[e].setZero();  // came apart
      touching[e] = touches;
      if (size == ContactBatch::kCapacity) {
        b.size = size;
        evaluate_batch(p, c, dt, update_history, b, f, tq);
        size = 0;
      }
    }
  };
  if (!mode) {  // no active region: the loop without its test
    for (long i = i0; i < i1; ++i) {
      if (i + kRowsAhead < i1) prefetch_far_partner(i + kRowsAhead);
      if (wrapping[i])
        scan_row(i, offset[i], offset[i + 1], std::true_type{}, std::false_type{});
      else
        scan_row(i, offset[i], offset[i + 1], std::false_type{}, std::false_type{});
    }
  } else {
    // The rows not kSkip: a pass over every row's mode, mispredicted at every change, cost 4 %
    // of a mostly sleeping pull, and a test of each partner of a held row whether it is held,
    // as much again.
    const int* rows = scanned_rows_.data();
    const int* listed = awake_start_.data();
    const int* rows_end = std::lower_bound(rows, rows + scanned_rows_.size(), i1);
    for (const int* k = std::lower_bound(rows, rows_end, i0); k != rows_end; ++k) {
      const long i = *k, r = k - rows;
      if (rows_end - k > kRowsAhead) prefetch_far_partner(k[kRowsAhead]);
      if (mode[i] == kAwakePartners) {
        if (wrapping[i])
          scan_row(i, listed[r], listed[r + 1], std::true_type{}, std::true_type{});
        else
          scan_row(i, listed[r], listed[r + 1], std::false_type{}, std::true_type{});
      } else if (wrapping[i]) {
        scan_row(i, offset[i], offset[i + 1], std::true_type{}, std::false_type{});
      } else {
        scan_row(i, offset[i], offset[i + 1], std::false_type{}, std::false_type{});
      }
    }
  }
  b.size = size;
  evaluate_batch(p, c, dt, update_history, b, f, tq);
}

void VerletContacts::prepare_accumulate() {
  planned_threads_ = omp_get_max_threads();
  if (static_cast<int>(thread_force_.size()) < planned_threads_) {
    thread_force_.resize(planned_threads_);
    thread_torque_.resize(planned_threads_);
  }
  while (static_cast<int>(batches_.size()) < planned_threads_)
    batches_.push_back(std::make_unique<ContactBatch>());
  if (static_cast<int>(row_split_.size()) != 2 * planned_threads_ + 1) balance_rows(planned_threads_);
}

void VerletContacts::accumulate_in_team(Particles& p, const Box& box, const ContactParams& c, double dt,
                                        bool update_history) {
  const int t = omp_get_thread_num(), nt = omp_get_num_threads();
  ContactBatch& b = *batches_[t];
  if (two_colours(nt)) {
    // Even blocks, then odd ones: no two blocks that run together write the same body, so
    // every thread adds into the particles' arrays, and nothing is left to sum.
    scan_rows(p, box, c, dt, update_history, row_split_[2 * t], row_split_[2 * t + 1], b, p.f.data(),
              p.torque.data());
#pragma omp barrier
    scan_rows(p, box, c, dt, update_history, row_split_[2 * t + 1], row_split_[2 * t + 2], b, p.f.data(),
              p.torque.data());
  } else {
    // Balanced for planned_threads_; a smaller team (nested or limited) takes whole blocks.
    // Thread 0 adds into the particles' arrays, the others into private copies, which
    // finish_accumulate() adds in thread order.
    const long n = static_cast<long>(p.size());
    const long blocks = static_cast<long>(row_split_.size()) - 1;
    const long i0 = row_split_[blocks * t / nt], i1 = row_split_[blocks * (t + 1) / nt];
    Vec3* f = p.f.data();
    Vec3* tq = p.torque.data();
    if (t > 0) {
      thread_force_[t].resize(n);
      thread_torque_[t].resize(n);
      for (const BodyRange& r : private_ranges(t, nt, n)) {
        std::fill(thread_force_[t].begin() + r.first, thread_force_[t].begin() + r.last, Vec3::Zero());
        std::fill(thread_torque_[t].begin() + r.first, thread_torque_[t].begin() + r.last, Vec3::Zero());
      }
      f = thread_force_[t].data();
      tq = thread_torque_[t].data();
    }
    scan_rows(p, box, c, dt, update_history, i0, i1, b, f, tq);
  }

  // Intruder pairs, into per-entry buffers that finish_accumulate() adds. They read no force,
  // so they need no barrier before them, and the one after the team's last scans covers them.
  const PairList& intruders = list_.intruder_pairs();
  const std::vector<int>& bodies = list_.intruder_bodies();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const int i = bodies[b];
#pragma omp for schedule(static) nowait
    for (int e = intruders.begin(b); e < intruders.end(b); ++e) {
      ContactGeometry g;
      if (!pair_geometry(p, box, i, intruders.partner[e], g)) {
        intruder_history_.shear[e].setZero();
        intruder_history_.touching[e] = 0;
        intruder_new_[e] = 0;
        intruder_force_[e].setZero();
        intruder_torque_[e].setZero();
        continue;
      }
      intruder_new_[e] = !intruder_history_.touching[e];
      intruder_history_.touching[e] = 1;
      const PairForce cf = hertz_history(c, g, dt, intruder_history_.shear[e], update_history);
      intruder_force_[e] = cf.force;
      intruder_torque_[e] = cf.torque;
    }
  }
}

void VerletContacts::finish_accumulate(Particles& p, long first, long last) {
  const int nt = omp_get_num_threads();
  if (!two_colours(nt) && nt > 1) {
    // The private arrays, in thread order (each body receives its terms in ascending s), each
    // over the ranges its thread cleared: nothing outside them was written.
    const long n = static_cast<long>(p.size());
    for (int s = 1; s < nt; ++s)
      for (const BodyRange& r : private_ranges(s, nt, n))
        for (long k = std::max(r.first, first); k < std::min(r.last, last); ++k) {
          p.f[k] += thread_force_[s][k];
          p.torque[k] += thread_torque_[s][k];
        }
  }
  // Then the intruder pairs, in list order: each thread walks them all and adds the share of
  // its own bodies, so every body receives its terms in the order a serial sum gives them.
  const PairList& intruders = list_.intruder_pairs();
  const std::vector<int>& bodies = list_.intruder_bodies();
  auto mine = [&](int k) { return first <= k && k < last; };
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const int i = bodies[b];
    const bool own_intruder = mine(i);
    for (int e = intruders.begin(b); e < intruders.end(b); ++e) {
      const int j = intruders.partner[e];
      if (own_intruder) {
        p.f[i] += intruder_force_[e];
        p.torque[i] -= p.radius[i] * intruder_torque_[e];
      }
      if (mine(j)) {
        p.f[j] -= intruder_force_[e];
        p.torque[j] -= p.radius[j] * intruder_torque_[e];
      }
    }
  }
}

std::vector<PairHistory> VerletContacts::export_history() const {
  std::vector<PairHistory> out;
  const PairList& pairs = list_.grain_pairs();
  for (std::size_t i = 0; i < pairs.rows(); ++i)
    for (int e = pairs.begin(i); e < pairs.end(i); ++e)
      if (grain_history_.touching[e])
        out.push_back({static_cast<int>(i), pairs.partner[e], grain_history_.shear[e]});
  const PairList& intruders = list_.intruder_pairs();
  for (std::size_t b = 0; b < intruders.rows(); ++b)
    for (int e = intruders.begin(b); e < intruders.end(b); ++e)
      if (intruder_history_.touching[e]) {
        // Stored (body, grain); exported in the canonical orientation i < j, seen from i.
        const int body = list_.intruder_bodies()[b], grain = intruders.partner[e];
        const Vec3& s = intruder_history_.shear[e];
        out.push_back({std::min(body, grain), std::max(body, grain), body < grain ? s : Vec3(-s)});
      }
  return out;
}

void VerletContacts::import_history(const std::vector<PairHistory>& history) {
  // Requires built lists (update_lists or rebuild first). History comes in the canonical
  // orientation (i < j, seen from i); intruder pairs are stored as (body, grain).
  auto find = [](const PairList& list, std::size_t row, int partner) {
    const auto first = list.partner.begin() + list.begin(row);
    const auto last = list.partner.begin() + list.end(row);
    const auto it = std::lower_bound(first, last, partner);
    return (it != last && *it == partner) ? static_cast<int>(it - list.partner.begin()) : -1;
  };
  const PairList& pairs = list_.grain_pairs();
  const PairList& intruders = list_.intruder_pairs();
  const std::vector<int>& bodies = list_.intruder_bodies();
  grain_history_.resize(pairs.size());  // the imported set replaces whatever was carried over
  forget_held_pairs();
  intruder_history_.resize(intruders.size());
  for (const PairHistory& h : history) {
    int e = -1;
    for (std::size_t b = 0; b < bodies.size() && e < 0; ++b) {
      if (bodies[b] == h.i || bodies[b] == h.j) {
        e = find(intruders, b, bodies[b] == h.i ? h.j : h.i);
        if (e >= 0) {
          intruder_history_.shear[e] = bodies[b] == h.i ? h.shear : Vec3(-h.shear);
          intruder_history_.touching[e] = 1;
        }
        break;
      }
    }
    if (e >= 0) continue;
    e = find(pairs, h.i, h.j);
    if (e >= 0) {
      grain_history_.shear[e] = h.shear;
      grain_history_.touching[e] = 1;
    }
  }
  balance_rows(omp_get_max_threads());
}

}  // namespace granudrag
