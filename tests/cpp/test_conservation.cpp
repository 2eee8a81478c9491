// Conservation laws of the integrator and contact law (no damping or friction where energy is
// concerned), and time reversibility of velocity Verlet.
#include <gtest/gtest.h>

#include <random>

#include "helpers.hpp"

using namespace granudrag;
using granudrag::support::ThreadCount;

namespace {

// A dense, hot packing: 400 grains in an fcc stack over the wall, random velocities.
Simulation hot_packing(const ContactParams& c, std::uint64_t seed) {
  LatticeBed bed = fcc_bed(400, seed);
  randomize_velocities(bed.particles, 0.5, 0.5, seed + 1);
  return Simulation(bed.particles, bed.box, c, Settings{});
}

// A free cluster far from any boundary, grains flying inward so that they collide.
Particles converging_cluster(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), d(0.9, 1.1);
  Particles p;
  const Vec3 centre(20, 20, 20);
  while (static_cast<int>(p.size()) < n) {
    const Vec3 x = centre + 3.0 * Vec3(u(rng), u(rng), u(rng));
    const double r = 0.5 * d(rng);
    bool free = true;
    for (std::size_t j = 0; j < p.size(); ++j)
      if ((p.x[j] - x).norm() < r + p.radius[j]) free = false;
    if (!free) continue;
    const std::size_t i = p.add(x, r, Species::Mobile);
    p.v[i] = -(x - centre) + 0.3 * Vec3(u(rng), u(rng), u(rng));
    p.omega[i] = 2.0 * Vec3(u(rng), u(rng), u(rng));
  }
  return p;
}

Vec3 linear_momentum(const Particles& p) {
  Vec3 m = Vec3::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) m += p.mass[i] * p.v[i];
  return m;
}

Vec3 angular_momentum(const Particles& p) {
  Vec3 l = Vec3::Zero();
  for (std::size_t i = 0; i < p.size(); ++i)
    l += p.mass[i] * p.x[i].cross(p.v[i]) + p.inertia(i) * p.omega[i];
  return l;
}

}  // namespace

TEST(Conservation, EnergyOfDensePackingOver1e5Steps) {
  Simulation sim = hot_packing(support::conservative_params(), 7);
  sim.setup();
  const Energy e0 = sim.energy();
  const double scale = e0.kinetic + e0.rotational;  // the energy that moves around
  double worst = 0;
  long contacts_seen = 0;
  for (int block = 0; block < 100; ++block) {
    sim.run(1000);
    const Energy e = sim.energy();
    worst = std::max(worst, std::abs(e.total() - e0.total()) / scale);
    if (e.elastic > 0) ++contacts_seen;
  }
  EXPECT_EQ(sim.steps_done(), 100000);
  EXPECT_GT(contacts_seen, 90);  // the packing stayed in contact: a real test of the forces
  // Bound: velocity Verlet has bounded energy error O((dt/t_c)^2); measured ~1e-4 here.
  EXPECT_LT(worst, 1e-3) << "max |E - E0| / E_kin0";
}

TEST(Conservation, EnergyIsDissipatedWithDamping) {
  Simulation sim = hot_packing(support::soft_params(0.5), 7);
  sim.setup();
  const double e0 = sim.energy().total();
  sim.run(5000);
  EXPECT_LT(sim.energy().total(), e0 - 0.1 * (e0 - sim.energy().potential));
}

TEST(Conservation, MomentumInCollisionsWithoutGravityOrWalls) {
  for (double mu : {0.0, 0.5}) {
    Particles p = converging_cluster(60, 3);
    Settings s;
    s.gravity = Vec3::Zero();
    Simulation sim(p, Box{40, 40, false}, support::soft_params(mu), s);
    const Vec3 p0 = linear_momentum(sim.particles());
    const Vec3 l0 = angular_momentum(sim.particles());
    double max_force = 0;
    for (int k = 0; k < 4000; ++k) {
      sim.step();
      for (const auto& f : sim.particles().f) max_force = std::max(max_force, f.norm());
    }
    EXPECT_GT(max_force, 1.0) << "no collisions happened";
    const double pscale = 0;
    (void)pscale;
    double momentum_scale = 0;
    for (std::size_t i = 0; i < p.size(); ++i) momentum_scale += p.mass[i] * p.v[i].norm();
    EXPECT_LT((linear_momentum(sim.particles()) - p0).norm() / momentum_scale, 1e-12);
    const double lscale = l0.norm() + 20.0 * momentum_scale;
    if (mu == 0.0) {
      // Central forces: exact up to rounding.
      EXPECT_LT((angular_momentum(sim.particles()) - l0).norm() / lscale, 1e-12);
    } else {
      // The LAMMPS convention applies the tangential force at R_i, R_j from the centres,
      // while the centres are R_i + R_j - delta apart: dL/dt = -delta n x F_t per contact, so
      // L drifts at the relative order of delta/d (~1e-3 here), not of 1.
      EXPECT_LT((angular_momentum(sim.particles()) - l0).norm() / lscale, 1e-3);
    }
  }
}

TEST(Conservation, TimeReversibility) {
  Simulation sim = hot_packing(support::conservative_params(), 11);
  const Particles start = sim.particles();
  sim.run(2000);
  double travelled = 0;
  for (std::size_t i = 0; i < start.size(); ++i)
    travelled = std::max(travelled, sim.box().min_image(sim.particles().x[i] - start.x[i]).norm());
  for (auto& v : sim.particles().v) v = -v;
  for (auto& w : sim.particles().omega) w = -w;
  sim.run(2000);
  double worst = 0;
  for (std::size_t i = 0; i < start.size(); ++i)
    worst = std::max(worst, sim.box().min_image(sim.particles().x[i] - start.x[i]).norm());
  EXPECT_GT(travelled, 0.1);  // it really went somewhere
  EXPECT_LT(worst, 1e-8);
}

TEST(Conservation, ViscousDampingDecaysAFreeGrainsVelocityExponentiallyFromItsStartTime) {
  // A grain alone in free space, no gravity: its velocity is kept until viscous_from, then decays
  // as exp(-viscous_damping t) (velocity Verlet with the drag at the half-step velocity: a factor
  // 1 - rate dt per step, within rate^2 dt t / 2 of the exponential); its spin likewise.
  Particles p;
  const std::size_t i = p.add(Vec3(5, 5, 5), 0.5, Species::Mobile);
  const Vec3 v0(1.0, -0.5, 0.25), w0(0.3, 0.0, -0.2);
  p.v[i] = v0;
  p.omega[i] = w0;
  Settings s;
  s.gravity = Vec3::Zero();
  s.dt = 5e-4;
  s.viscous_damping = 2.0;
  s.viscous_from = 0.5;
  Simulation sim(p, Box{10, 10, false}, support::soft_params(0.5), s);
  sim.run(1000);
  EXPECT_EQ(sim.particles().v[i], v0) << "no drag before viscous_from";
  EXPECT_EQ(sim.particles().omega[i], w0);
  sim.run(2000);
  const double expected = std::exp(-2.0 * 1.0);
  EXPECT_NEAR(sim.particles().v[i].norm() / v0.norm(), expected, 3e-3 * expected);
  EXPECT_LT((sim.particles().v[i].normalized() - v0.normalized()).norm(), 1e-12);
  EXPECT_NEAR(sim.particles().omega[i].norm() / w0.norm(), expected, 3e-3 * expected);
  EXPECT_LT((sim.particles().omega[i].normalized() - w0.normalized()).norm(), 1e-12);
}
