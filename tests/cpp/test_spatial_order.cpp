// The spatial order (core/spatial_order.hpp) and the two-colour schedule it serves
// (contact/verlet_contacts.cpp): a sweep along the longer horizontal axis of a wide bed, whose
// periodic boundary the colour check must allow without letting two blocks of one colour write
// the same body; a state carried through the permutation; a pull that steps a bed in that order,
// writes its frames in the bed's, and resumes bitwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "contact/verlet_contacts.hpp"
#include "core/balanced_split.hpp"
#include "core/spatial_order.hpp"
#include "helpers.hpp"
#include "protocol/pull.hpp"

using namespace granudrag;
using granudrag::support::ThreadCount;

namespace {

// A bed much wider than deep, 24 d x 6 d and about 9 d high, D = 2 at depth 4: it sweeps along
// x, and at 4 threads (8 blocks of 3 d) the periodic seam's writes come close to the last
// blocks' own.
const Bed& wide_bed() {
  static const Bed bed = [] {
    PourSpec s;
    s.lx = 24;
    s.ly = 6;
    s.grains = 1500;
    s.intruder_diameter = 2;
    s.intruder_x = 12;
    s.intruder_y = 3;
    s.depth = 4;
    s.contact = ContactParams{}.with_stiffness(2e4);
    s.ke_threshold = 1e-3;
    s.max_settle_time = 15;
    return pour(s, false);
  }();
  return bed;
}

bool is_permutation_of_n(const std::vector<std::size_t>& order, std::size_t n) {
  std::vector<std::size_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::size_t> all(n);
  std::iota(all.begin(), all.end(), 0);
  return sorted == all;
}

// The bodies block b writes: its rows and their partners.
std::set<int> written(const PairList& pairs, const std::vector<long>& split, int b) {
  std::set<int> w;
  for (long r = split[b]; r < split[b + 1]; ++r) {
    w.insert(static_cast<int>(r));
    for (int e = pairs.begin(r); e < pairs.end(r); ++e) w.insert(pairs.partner[e]);
  }
  return w;
}

// Whether no two blocks of one colour write the same body, body by body.
bool colours_disjoint(const PairList& pairs, const std::vector<long>& split) {
  const int blocks = static_cast<int>(split.size()) - 1;
  std::vector<std::set<int>> w(blocks);
  for (int b = 0; b < blocks; ++b) w[b] = written(pairs, split, b);
  for (int b = 0; b < blocks; ++b)
    for (int c = b + 2; c < blocks; c += 2)
      for (int body : w[b])
        if (w[c].count(body)) return false;
  return true;
}

// A chain of n bodies on a ring: row i holds i + 1 .. i + reach, and the rows near 0 hold the
// bodies near n - 1 across the seam (partners j > i, as the lists store them).
PairList ring(int n, int reach) {
  PairList list;
  list.offset.assign(1, 0);
  for (int i = 0; i < n; ++i) {
    std::vector<int> row;
    for (int d = 1; d <= reach; ++d) {
      const int j = (i + d) % n;
      if (j > i) row.push_back(j);
    }
    for (int d = 1; d <= reach; ++d) {
      const int j = ((i - d) % n + n) % n;
      if (j > i + reach) row.push_back(j);  // across the seam
    }
    std::sort(row.begin(), row.end());
    list.partner.insert(list.partner.end(), row.begin(), row.end());
    list.offset.push_back(static_cast<int>(list.partner.size()));
  }
  return list;
}

std::vector<long> even_split(long n, int blocks) {
  std::vector<long> split(blocks + 1);
  for (int b = 0; b <= blocks; ++b) split[b] = n * b / blocks;
  return split;
}

}  // namespace

TEST(SpatialOrder, IsAPermutationWithIntrudersLastSweepingAWideBedAlongItsLongerAxis) {
  const Particles& p = wide_bed().state.particles;
  const Box& box = wide_bed().box;
  EXPECT_EQ(sweep_axis(p, box), SweepAxis::X);
  EXPECT_EQ(sweep_axis(support::small_bed().state.particles, support::small_bed().box), SweepAxis::Z);
  // The same bed turned by a right angle sweeps along y.
  Particles turned = p;
  for (Vec3& x : turned.x) x = Vec3(x.y(), x.x(), x.z());
  EXPECT_EQ(sweep_axis(turned, Box{box.ly, box.lx, true}), SweepAxis::Y);
  for (SweepAxis axis : {SweepAxis::Auto, SweepAxis::X, SweepAxis::Y, SweepAxis::Z}) {
    const std::vector<std::size_t> order = spatial_order(p, box, axis);
    ASSERT_TRUE(is_permutation_of_n(order, p.size()));
    ASSERT_EQ(p.species[order.back()], Species::Intruder);
    for (std::size_t k = 0; k + 1 < order.size(); ++k) ASSERT_NE(p.species[order[k]], Species::Intruder);
    const std::vector<std::size_t> rank = inverse_order(order);
    for (std::size_t k = 0; k < order.size(); ++k) ASSERT_EQ(rank[order[k]], k);
  }
  // Along x, in quarter-diameter layers.
  const std::vector<std::size_t> order = spatial_order(p, box);
  for (std::size_t k = 0; k + 2 < order.size(); ++k)
    ASSERT_LE(std::floor(p.x[order[k]].x() / 0.25), std::floor(p.x[order[k + 1]].x() / 0.25)) << k;
  const Particles q = reordered(p, order);
  for (std::size_t k = 0; k < order.size(); ++k) {
    ASSERT_EQ(q.x[k], p.x[order[k]]);
    ASSERT_EQ(q.radius[k], p.radius[order[k]]);
    ASSERT_EQ(q.species[k], p.species[order[k]]);
  }
}

TEST(SpatialOrder, TheColourCheckAllowsAPeriodicSeamWhileItsWritesStayApart) {
  // 400 bodies on a ring, partners 3 ahead: block 0 reaches across the seam into the last 3.
  const PairList list = ring(400, 3);
  EXPECT_TRUE(colour_blocks_apart(list, even_split(400, 4)));
  EXPECT_TRUE(colours_disjoint(list, even_split(400, 4)));
  // A last block of 5 bodies: block 0's seam partners (397 .. 399) meet the partners of block 2
  // (its rows end at 394, reaching 397).
  const std::vector<long> thin_last = {0, 100, 200, 395, 400};
  EXPECT_FALSE(colours_disjoint(list, thin_last));
  EXPECT_FALSE(colour_blocks_apart(list, thin_last));
  // A block's partners reaching past the next block: two blocks of a colour meet.
  const std::vector<long> thin_middle = {0, 100, 102, 300, 400};
  EXPECT_FALSE(colours_disjoint(list, thin_middle));
  EXPECT_FALSE(colour_blocks_apart(list, thin_middle));
}

TEST(SpatialOrder, TheColourCheckNeverPassesBlocksOfAColourThatWriteTheSameBody) {
  // Random lists, near partners with a few far ones anywhere, and random splits: whenever the
  // check passes, the written sets are disjoint, body by body; it passes often enough to matter.
  std::mt19937_64 rng(29);
  int passed = 0, failed = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 60 + static_cast<int>(rng() % 200);
    const int reach = 1 + static_cast<int>(rng() % 6);
    const double far_chance = (rng() % 4 == 0) ? 0.0 : 0.02 * static_cast<double>(rng() % 4);
    std::uniform_real_distribution<double> u(0, 1);
    PairList list;
    list.offset.assign(1, 0);
    for (int i = 0; i < n; ++i) {
      std::set<int> row;
      for (int d = 1; d <= reach; ++d)
        if (i + d < n && u(rng) < 0.7) row.insert(i + d);
      if (i + 1 < n && u(rng) < far_chance) row.insert(i + 1 + static_cast<int>(rng() % (n - i - 1)));
      list.partner.insert(list.partner.end(), row.begin(), row.end());
      list.offset.push_back(static_cast<int>(list.partner.size()));
    }
    const int blocks = 2 * (1 + static_cast<int>(rng() % 4));
    std::vector<long> split(blocks + 1, 0);
    split[blocks] = n;
    for (int b = 1; b < blocks; ++b) split[b] = static_cast<long>(rng() % (n + 1));
    std::sort(split.begin(), split.end());
    if (colour_blocks_apart(list, split)) {
      ASSERT_TRUE(colours_disjoint(list, split)) << "trial " << trial;
      ++passed;
    } else {
      ++failed;
    }
  }
  EXPECT_GT(passed, 50);
  EXPECT_GT(failed, 50);
}

TEST(SpatialOrder, APouredBedSweptAlongXTakesTheTwoColoursOnTwoAndFourThreadsWithTheSameForces) {
  // The bed's grains in random order take private force arrays; swept along x they take the two
  // colours, the seam included, and every body feels the force it felt in the serial order.
  const Bed& bed = wide_bed();
  const ContactParams c = bed.contact;
  Particles shuffled_p;
  {
    std::vector<std::size_t> order(bed.state.particles.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end() - 1, std::mt19937_64(5));  // the intruder stays last
    shuffled_p = reordered(bed.state.particles, order);
  }
  Settings s;
  s.dt = bed.dt;
  std::vector<Vec3> reference;
  {
    ThreadCount tc(1);
    Simulation serial(shuffled_p, bed.box, c, s);
    serial.setup();
    reference = serial.particles().f;
  }
  double scale = 0;
  for (const Vec3& f : reference) scale = std::max(scale, f.norm());
  const std::vector<std::size_t> order = spatial_order(shuffled_p, bed.box);
  const Particles sorted_p = reordered(shuffled_p, order);
  for (int threads : {2, 4}) {
    ThreadCount tc(threads);
    Simulation shuffled(shuffled_p, bed.box, c, s), sorted(sorted_p, bed.box, c, s);
    shuffled.setup();
    sorted.setup();
    const auto& lists = dynamic_cast<const VerletContacts&>(sorted.contacts());
    EXPECT_FALSE(dynamic_cast<const VerletContacts&>(shuffled.contacts()).colored()) << threads;
    EXPECT_TRUE(lists.colored()) << threads;
    // The seam is there: rows of the first layers hold partners among the last bodies.
    const PairList& pairs = lists.list().grain_pairs();
    const long n = static_cast<long>(pairs.rows());
    long across = 0;
    for (long r = 0; r < n / 10; ++r)
      for (int e = pairs.begin(r); e < pairs.end(r); ++e) across += pairs.partner[e] > n - n / 10;
    EXPECT_GT(across, 20) << threads;
    // The schedule's blocks split the rows by cost; any split the check passes writes disjoint
    // sets of bodies per colour, checked body by body on this bed's lists.
    std::vector<long> cost(n + 1, 0), split;
    for (long r = 0; r < n; ++r) cost[r + 1] = cost[r] + 1 + pairs.end(r) - pairs.begin(r);
    balanced_split(cost, 2 * threads, split);
    ASSERT_TRUE(colour_blocks_apart(pairs, split)) << threads;
    EXPECT_TRUE(colours_disjoint(pairs, split)) << threads;
    for (std::size_t k = 0; k < order.size(); ++k)
      ASSERT_LT(support::rel_diff(sorted.particles().f[k], reference[order[k]], scale), 1e-12)
          << k << ", threads " << threads;
  }
}

TEST(SpatialOrder, AReorderedStateGoesOnWithTheSameForcesAndSprings) {
  // The bed's state (its springs carried from the pour) in the sweep's order: the same forces
  // and springs, found through the permutation, after steps with the intruder moving.
  ThreadCount tc(1);
  const Bed& bed = wide_bed();
  Settings s;
  s.dt = bed.dt;
  Simulation plain(bed.state.particles, bed.box, bed.contact, s);
  plain.restore(bed.state);
  const std::vector<std::size_t> order = spatial_order(bed.state.particles, bed.box);
  const Simulation::State state = reordered(bed.state, order);
  ASSERT_FALSE(bed.state.pair_history.empty());
  Simulation sorted(state.particles, bed.box, bed.contact, s);
  sorted.restore(state);
  const std::vector<std::size_t> rank = inverse_order(order);
  plain.particles().v[bed.intruder] = Vec3(1, 0, 0);
  sorted.particles().v[rank[bed.intruder]] = Vec3(1, 0, 0);
  plain.run(200);
  sorted.run(200);
  double scale = 0;
  for (const Vec3& f : plain.particles().f) scale = std::max(scale, f.norm());
  for (std::size_t k = 0; k < order.size(); ++k) {
    ASSERT_LT(support::rel_diff(sorted.particles().f[k], plain.particles().f[order[k]], scale), 1e-12) << k;
    ASSERT_LT((sorted.particles().x[k] - plain.particles().x[order[k]]).norm(), 1e-12) << k;
  }
  // Every spring, renamed and in the canonical orientation.
  std::vector<PairHistory> a = plain.state().pair_history, b = sorted.state().pair_history;
  ASSERT_EQ(a.size(), b.size());
  double shear_scale = 0;
  for (PairHistory& h : a) {
    shear_scale = std::max(shear_scale, h.shear.norm());
    const int i = static_cast<int>(rank[h.i]), j = static_cast<int>(rank[h.j]);
    h = i < j ? PairHistory{i, j, h.shear} : PairHistory{j, i, Vec3(-h.shear)};
  }
  auto by_pair = [](const PairHistory& x, const PairHistory& y) {
    return std::pair(x.i, x.j) < std::pair(y.i, y.j);
  };
  std::sort(a.begin(), a.end(), by_pair);
  std::sort(b.begin(), b.end(), by_pair);
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].i, b[k].i);
    ASSERT_EQ(a[k].j, b[k].j);
    ASSERT_LT((a[k].shear - b[k].shear).norm(), 1e-12 * shear_scale) << k;
  }
}

TEST(SpatialOrder, APullStepsTheBedSweptAlongXResumesBitwiseAndShowsTheBedsOrder) {
  // On 2 threads (the two colours across the seam): a pull resumed from its checkpoint takes
  // the same order again and ends bitwise as the uninterrupted one; the frames' particles are
  // the bed's, in its order.
  ThreadCount tc(2);
  const Bed& bed = wide_bed();
  PullSpec spec;
  spec.speed = 0.5;
  spec.distance = 1.0;
  spec.checkpoint_every = 400;
  Pull whole(bed, spec);
  EXPECT_EQ(whole.order(), spatial_order(bed.state.particles, bed.box));
  EXPECT_NE(whole.order(), inverse_order(whole.order()));  // not the bed's order
  EXPECT_EQ(whole.simulation().particles().species[whole.intruder()], Species::Intruder);
  EXPECT_TRUE(dynamic_cast<const VerletContacts&>(whole.simulation().contacts()).colored());
  const Particles start = whole.particles_in_bed_order();
  EXPECT_EQ(start.x, bed.state.particles.x);
  EXPECT_EQ(start.radius, bed.state.particles.radius);
  EXPECT_EQ(start.species, bed.state.particles.species);
  const support::Checkpoints checkpoints = support::run_keeping_checkpoints(whole);
  ASSERT_GE(checkpoints.size(), 2u);
  Pull resumed(bed, spec, checkpoints[0].first, checkpoints[0].second);
  resumed.run(false, [](const Pull&) {});
  EXPECT_EQ(whole.simulation().particles().x, resumed.simulation().particles().x);
  EXPECT_EQ(whole.simulation().particles().v, resumed.simulation().particles().v);
  EXPECT_EQ(whole.simulation().particles().omega, resumed.simulation().particles().omega);
  EXPECT_EQ(whole.record().fx, resumed.record().fx);
  // The intruder, found in the bed's order, has moved along x only.
  const Particles end = whole.particles_in_bed_order();
  EXPECT_EQ(end.x[bed.intruder].z(), bed.state.particles.x[bed.intruder].z());
  EXPECT_GT(end.x[bed.intruder].x(), bed.state.particles.x[bed.intruder].x() + 0.9);
}
