// Placing an intruder into a settled bed: the grains removed are exactly those the intruder's
// volume cuts (against a brute-force scan), the kept pairs' histories survive renumbered, bad
// input is refused by name, and the bed settles again around the held intruder at its depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/error.hpp"
#include "protocol/placement.hpp"
#include "protocol/pour.hpp"

using namespace granudrag;

namespace {

// One settled column without an intruder, poured once for the whole file.
const Bed& column() {
  static const Bed bed = [] {
    PourSpec s;
    s.lx = s.ly = 8;
    s.grains = 700;
    s.intruder_diameter = 0;
    s.seed = 3;
    s.contact = ContactParams{}.with_stiffness(2e4);
    s.contact.mu = 0.5;
    s.ke_threshold = 1e-5;
    s.max_settle_time = 30;
    return pour(s, false);
  }();
  return bed;
}

PlacementSpec spec(double D, double depth) {
  PlacementSpec s;
  s.intruder_diameter = D;
  s.depth = depth;
  s.ke_threshold = 1e-5;
  return s;
}

std::string message(const Bed& source, const PlacementSpec& s) {
  try {
    placed_column(source, s, nullptr);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Placement, RemovesExactlyTheGrainsTheIntruderCuts) {
  const Bed& src = column();
  ASSERT_EQ(src.stop_reason, "threshold");
  PlacementRecord rec;
  const Bed placed = placed_column(src, spec(2, 3), &rec);
  const Particles& p = src.state.particles;
  const Vec3 c(4, 4, src.surface_height - 3);
  std::set<long> cut;  // brute force, with the periodic images by hand
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int ix = -1; ix <= 1; ++ix)
      for (int iy = -1; iy <= 1; ++iy)
        if ((p.x[i] + Vec3(8.0 * ix, 8.0 * iy, 0) - c).norm() < 1.0 + p.radius[i])
          cut.insert(static_cast<long>(i));
  ASSERT_FALSE(cut.empty());
  EXPECT_EQ(std::set<long>(rec.removed.begin(), rec.removed.end()), cut);
  const Particles& q = placed.state.particles;
  ASSERT_EQ(q.size(), p.size() - cut.size() + 1);
  EXPECT_EQ(placed.intruder, static_cast<int>(q.size()) - 1);
  EXPECT_EQ(q.species[placed.intruder], Species::Intruder);
  EXPECT_DOUBLE_EQ(q.radius[placed.intruder], 1.0);
  EXPECT_DOUBLE_EQ(rec.intruder_z, src.surface_height - 3);
  for (std::size_t i = 0; i + 1 < q.size(); ++i)
    EXPECT_GE(placed.box.min_image(q.x[i] - c).norm(), 1.0 + q.radius[i]) << "grain " << i << " still cut";
  // Every kept pair's spring, renumbered; none of a removed grain.
  std::size_t kept_pairs = 0;
  for (const PairHistory& h : src.state.pair_history) kept_pairs += !cut.count(h.i) && !cut.count(h.j);
  ASSERT_EQ(placed.state.pair_history.size(), kept_pairs);
  std::vector<long> old_of;  // new index -> source index
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!cut.count(static_cast<long>(i))) old_of.push_back(static_cast<long>(i));
  for (const PairHistory& h : placed.state.pair_history) {
    const Vec3 a = q.x[h.i], b = q.x[h.j];
    EXPECT_EQ(a, p.x[old_of[h.i]]);
    EXPECT_EQ(b, p.x[old_of[h.j]]);
  }
  // The source is read only.
  EXPECT_EQ(src.state.particles.size(), p.size());
  EXPECT_EQ(src.intruder, -1);
}

TEST(Placement, RefusesBadInputByName) {
  const Bed& src = column();
  EXPECT_NE(message(src, spec(2, 40)).find("'depth' = 40 is deeper than the bed"), std::string::npos);
  EXPECT_NE(message(src, spec(5, 3)).find("'intruder_diameter' = 5 does not fit the box"), std::string::npos);
  EXPECT_NE(message(src, spec(2, NAN)).find("give 'depth'"), std::string::npos);
  PlacementSpec far = spec(2, 3);
  far.intruder_x = 9;
  EXPECT_NE(message(src, far).find("outside the box"), std::string::npos);
  Bed moving = src;
  moving.kinetic_energy = 1.0;
  EXPECT_EQ(message(moving, spec(2, 3)), "");  // it reached its own pour's threshold
  moving.stop_reason = "max_time";
  EXPECT_NE(message(moving, spec(2, 3)).find("never settled"), std::string::npos);
  Bed with_intruder = placed_column(src, spec(2, 3), nullptr);
  EXPECT_NE(message(with_intruder, spec(2, 3)).find("already has an intruder"), std::string::npos);
}

TEST(Placement, TheBedSettlesAroundTheHeldIntruderAtItsDepth) {
  const Bed& src = column();
  const PlacementSpec s = spec(2, 3);
  PlacementRecord rec;
  Placement settling(placed_column(src, s, &rec), s);
  settling.run(false);
  const Bed& bed = settling.result();
  EXPECT_EQ(bed.stop_reason, "threshold");
  EXPECT_LT(bed.kinetic_energy, s.ke_threshold);
  EXPECT_GE(bed.settle_time, s.min_settle_time);
  // Held: the intruder has not moved.
  EXPECT_EQ(bed.state.particles.x[bed.intruder], Vec3(4, 4, rec.intruder_z));
  // The grains around it fill the cut shell a little; the surface stays within a few tenths.
  EXPECT_NEAR(bed.surface_height, src.surface_height, 0.3);
  EXPECT_NEAR(bed.depth, 3.0, 0.3);
  EXPECT_DOUBLE_EQ(bed.depth, bed.surface_height - rec.intruder_z);
  EXPECT_EQ(bed.state.steps, 0);
}
