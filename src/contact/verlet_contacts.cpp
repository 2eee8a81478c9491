#include "contact/verlet_contacts.hpp"

#include <omp.h>

#include <algorithm>
#include <memory>
#include <type_traits>

#include "contact/contact_batch.hpp"
#include "contact/contact_law.hpp"
#include "core/balanced_split.hpp"
#include "core/ordered_sum.hpp"

namespace granudrag {

namespace {

// Geometry of the pair (i, j) if it touches; false otherwise.
inline bool pair_geometry(const Particles& p, const Box& box, int i, int j, ContactGeometry& g) {
  g.del = box.min_image(p.x[i] - p.x[j]);
  const double rsq = g.del.squaredNorm();
  const double radsum = p.radius[i] + p.radius[j];
  if (rsq >= radsum * radsum) return false;
  g.r = std::sqrt(rsq);
  g.contact_distance = radsum;
  g.reff = p.radius[i] * p.radius[j] / radsum;
  g.meff = effective_mass(p.mass[i], p.species[i], p.mass[j], p.species[j]);
  g.rel_velocity = p.v[i] - p.v[j];
  g.spin_sum = p.radius[i] * p.omega[i] + p.radius[j] * p.omega[j];
  return true;
}

}  // namespace

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
  balance_rows(omp_get_max_threads());
}

void VerletContacts::balance_rows(int threads) {
  // With the batched law a touching pair costs about two near misses (the scan, then the
  // gather, law and scatter); weights 1, 2 and 4 measured on a 7.7k pull with 2 threads: the
  // force loop took 0.55, 0.57 and 0.57 s.
  constexpr long kTouchWeight = 1;
  const PairList& pairs = list_.grain_pairs();
  const long n = static_cast<long>(pairs.rows());
  const std::uint8_t* touching = grain_history_.touching.data();
  std::vector<long> cost(n + 1, 0);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {
    long c = 1 + pairs.end(i) - pairs.begin(i);
    for (int e = pairs.begin(i); e < pairs.end(i); ++e) c += kTouchWeight * touching[e];
    cost[i + 1] = c;
  }
  for (long i = 0; i < n; ++i) cost[i + 1] += cost[i];
  // Two blocks of rows per thread, of equal cost: thread t runs blocks 2t and 2t + 1.
  const int blocks = 2 * threads;
  balanced_split(cost, blocks, row_split_);
  // The blocks can be run in two colours, even blocks together and then odd ones, writing
  // straight into the particles' forces, when no block's partners reach the next block of its
  // colour. Grains poured by granudrag are ordered in space (pour.cpp), so a row's partners lie
  // within a layer of it in index; a bed in another order (imported) takes private arrays.
  colored_ = threads > 1;
  for (int b = 0; b + 2 <= blocks && colored_; ++b) {
    int reach = -1;  // the largest partner of the block's rows (rows are sorted)
    for (long r = row_split_[b]; r < row_split_[b + 1]; ++r)
      if (pairs.end(r) > pairs.begin(r)) reach = std::max(reach, pairs.partner[pairs.end(r) - 1]);
    colored_ = reach < row_split_[b + 2];
  }
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
  std::uint8_t* touching = grain_history_.touching.data();
  Vec3* shear = grain_history_.shear.data();
  int size = 0;
  // One row; `periodic`: its partners may lie across a boundary. Most rows have none, and
  // skip the minimum image's compares and jumps (a fifth of the scan's instructions).
  auto scan_row = [&](long i, auto periodic) {
    // Plain doubles rather than Vec3 here: Eigen packs x, y into one register and z into
    // another, and the shuffles and spills cost more than the arithmetic.
    const double xi = x[i].x(), yi = x[i].y(), zi = x[i].z();
    const double ri = radius[i];
    const int end = offset[i + 1];
    for (int e = offset[i]; e < end; ++e) {
      const int j = partner[e];
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
  for (long i = i0; i < i1; ++i) {
    if (wrapping[i])
      scan_row(i, std::true_type{});
    else
      scan_row(i, std::false_type{});
  }
  b.size = size;
  evaluate_batch(p, c, dt, update_history, b, f, tq);
}

void VerletContacts::accumulate(Particles& p, const Box& box, const ContactParams& c, double dt,
                                bool update_history) {
  const long n = static_cast<long>(p.size());
  const int max_threads = omp_get_max_threads();
  if (static_cast<int>(thread_force_.size()) < max_threads) {
    thread_force_.resize(max_threads);
    thread_torque_.resize(max_threads);
  }
  while (static_cast<int>(batches_.size()) < max_threads)
    batches_.push_back(std::make_unique<ContactBatch>());
  if (static_cast<int>(row_split_.size()) != 2 * max_threads + 1) balance_rows(max_threads);

#pragma omp parallel
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    ContactBatch& b = *batches_[t];
    if (colored_ && nt == max_threads) {
      // Even blocks, then odd ones: no two blocks that run together write the same body, so
      // every thread adds into the particles' arrays, and no reduction follows.
      scan_rows(p, box, c, dt, update_history, row_split_[2 * t], row_split_[2 * t + 1], b, p.f.data(),
                p.torque.data());
#pragma omp barrier
      scan_rows(p, box, c, dt, update_history, row_split_[2 * t + 1], row_split_[2 * t + 2], b, p.f.data(),
                p.torque.data());
    } else {
      // Balanced for max_threads; a smaller team (nested or limited) takes whole blocks.
      // Thread 0 adds into the particles' arrays, the others into private copies summed in
      // thread order afterwards.
      const long blocks = static_cast<long>(row_split_.size()) - 1;
      auto first_row = [&](int s) { return row_split_[blocks * s / nt]; };
      const long i0 = first_row(t), i1 = first_row(t + 1);
      Vec3* f = p.f.data();
      Vec3* tq = p.torque.data();
      if (t > 0) {
        // Partners j > i >= i0: the private arrays need only that range.
        thread_force_[t].resize(n);
        thread_torque_[t].resize(n);
        std::fill(thread_force_[t].begin() + i0, thread_force_[t].end(), Vec3::Zero());
        std::fill(thread_torque_[t].begin() + i0, thread_torque_[t].end(), Vec3::Zero());
        f = thread_force_[t].data();
        tq = thread_torque_[t].data();
      }
      scan_rows(p, box, c, dt, update_history, i0, i1, b, f, tq);
#pragma omp barrier
      if (nt > 1) {
#pragma omp for schedule(static)
        for (long k = 0; k < n; ++k) {
          for (int s = 1; s < nt; ++s) {
            if (k < first_row(s)) break;
            p.f[k] += thread_force_[s][k];
            p.torque[k] += thread_torque_[s][k];
          }
        }
      }
    }

    // Intruder pairs: evaluated in parallel into per-entry buffers, summed serially below.
    const PairList& intruders = list_.intruder_pairs();
    const std::vector<int>& bodies = list_.intruder_bodies();
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const int i = bodies[b];
#pragma omp for schedule(static)
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

  const PairList& intruders = list_.intruder_pairs();
  const std::vector<int>& bodies = list_.intruder_bodies();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const int i = bodies[b];
    for (int e = intruders.begin(b); e < intruders.end(b); ++e) {
      const int j = intruders.partner[e];
      p.f[i] += intruder_force_[e];
      p.torque[i] -= p.radius[i] * intruder_torque_[e];
      p.f[j] -= intruder_force_[e];
      p.torque[j] -= p.radius[j] * intruder_torque_[e];
    }
  }
}

// The checks below run every sample interval (the run guard, the coordination numbers): in
// parallel over the rows, or on a study's interval of 40 steps they cost 7 % of a 2-thread pull.
double VerletContacts::elastic_energy(const Particles& p, const Box& box, const ContactParams& c) const {
  auto pair_energy = [&](int i, int j) {
    ContactGeometry g;
    return pair_geometry(p, box, i, j, g) ? hertz_normal_energy(c.kn, g.reff, g.contact_distance - g.r) : 0.0;
  };
  const PairList& pairs = list_.grain_pairs();
  double energy = ordered_sum<double>(static_cast<long>(pairs.rows()), [&](long i) {
    double row = 0.0;
    for (int e = pairs.begin(i); e < pairs.end(i); ++e)
      row += pair_energy(static_cast<int>(i), pairs.partner[e]);
    return row;
  });
  const PairList& intruders = list_.intruder_pairs();
  for (std::size_t b = 0; b < intruders.rows(); ++b)
    for (int e = intruders.begin(b); e < intruders.end(b); ++e)
      energy += pair_energy(list_.intruder_bodies()[b], intruders.partner[e]);
  return energy;
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

void VerletContacts::count_contacts(std::vector<int>& contacts) const {
  // A row's partners belong to other threads' rows: threads past the first count into private
  // arrays, added afterwards (integers: the same result in any order). Atomic increments instead
  // made one thread slower than the serial pass.
  const PairList& pairs = list_.grain_pairs();
  const long rows = static_cast<long>(pairs.rows()), n = static_cast<long>(contacts.size());
  std::vector<std::vector<int>> extra(omp_get_max_threads());
#pragma omp parallel
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    if (t > 0) extra[t].assign(n, 0);
    int* count = t == 0 ? contacts.data() : extra[t].data();
    for (long i = rows * t / nt; i < rows * (t + 1) / nt; ++i)
      for (int e = pairs.begin(i); e < pairs.end(i); ++e)
        if (grain_history_.touching[e]) {
          ++count[i];
          ++count[pairs.partner[e]];
        }
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

double VerletContacts::max_overlap(const Particles& p, const Box& box) const {
  auto overlap = [&](int i, int j) {
    return p.radius[i] + p.radius[j] - box.min_image(p.x[i] - p.x[j]).norm();
  };
  const PairList& pairs = list_.grain_pairs();
  const long rows = static_cast<long>(pairs.rows());
  double worst = 0;  // the largest is the same whatever the order
#pragma omp parallel for schedule(static) reduction(max : worst)
  for (long i = 0; i < rows; ++i)
    for (int e = pairs.begin(i); e < pairs.end(i); ++e)
      if (grain_history_.touching[e]) worst = std::max(worst, overlap(static_cast<int>(i), pairs.partner[e]));
  const PairList& intruders = list_.intruder_pairs();
  for (std::size_t b = 0; b < intruders.rows(); ++b)
    for (int e = intruders.begin(b); e < intruders.end(b); ++e)
      if (intruder_history_.touching[e])
        worst = std::max(worst, overlap(list_.intruder_bodies()[b], intruders.partner[e]));
  return worst;
}

long VerletContacts::contact_count() const {
  long n = 0;
  for (auto t : grain_history_.touching) n += t;
  for (auto t : intruder_history_.touching) n += t;
  return n;
}

}  // namespace granudrag
