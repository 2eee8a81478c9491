#include "protocol/pour.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <sstream>

#include "core/error.hpp"
#include "engine/run_guard.hpp"

namespace granudrag {

namespace {

constexpr double kMeanCubeDiameter = 1.01;  // E[d^3] for d uniform in [0.9, 1.1]

double grain_volume_estimate(long n) { return n * M_PI / 6.0 * kMeanCubeDiameter; }

}  // namespace

double bulk_packing_estimate(double mu) {
  static const double table[][2] = {{0.0, 0.657}, {0.1, 0.633}, {0.2, 0.624},
                                    {0.3, 0.619}, {0.5, 0.604}, {0.9, 0.598}};
  const int n = sizeof table / sizeof table[0];
  if (!(mu > table[0][0])) return table[0][1];
  for (int i = 1; i < n; ++i)
    if (mu <= table[i][0]) {
      const double w = (mu - table[i - 1][0]) / (table[i][0] - table[i - 1][0]);
      return (1 - w) * table[i - 1][1] + w * table[i][1];
    }
  return table[n - 1][1];
}

namespace {
// The spec's packing_estimate if given, else the measured one for its friction.
double assumed_packing(const PourSpec& s) {
  return std::isnan(s.packing_estimate) ? bulk_packing_estimate(s.contact.mu) : s.packing_estimate;
}
}  // namespace

double intruder_height_for_depth(const PourSpec& s) {
  const double R = 0.5 * s.intruder_diameter;
  const double intruder_volume = 4.0 / 3.0 * M_PI * R * R * R;
  const double height =
      (grain_volume_estimate(s.grains) / assumed_packing(s) + intruder_volume) / (s.lx * s.ly) +
      kSurfaceOffset;
  const double z = height - s.depth;
  if (z - R < s.base_height + 0.5) {
    std::ostringstream msg;
    msg << "'depth' = " << s.depth << " is deeper than the bed: " << s.grains << " grains in " << s.lx
        << " x " << s.ly << " make a bed about " << height
        << " d high, so the intruder (D = " << s.intruder_diameter
        << ") fits above the base for depth <= " << height - R - s.base_height - 0.5
        << "; use fewer d of depth or more grains";
    throw Error(msg.str());
  }
  return z;
}

Particles place_grains(const PourSpec& s, double intruder_z, double* column_top) {
  std::mt19937_64 rng(s.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double R = 0.5 * s.intruder_diameter;
  const Vec3 intruder(s.intruder_x, s.intruder_y, intruder_z);
  const double intruder_volume = R > 0 ? 4.0 / 3.0 * M_PI * R * R * R : 0.0;
  const double top =
      (grain_volume_estimate(s.grains) / s.fill_fraction + intruder_volume) / (s.lx * s.ly) + 1.1;
  *column_top = top;

  // Hash grid for overlap checks: cells of 1.1 d, periodic in x and y.
  const int nx = std::max(1, static_cast<int>(s.lx / 1.1)), ny = std::max(1, static_cast<int>(s.ly / 1.1));
  const int nz = static_cast<int>(top / 1.1) + 1;
  const double cx = s.lx / nx, cy = s.ly / ny, cz = 1.1;
  std::vector<std::vector<int>> cells(static_cast<std::size_t>(nx) * ny * nz);
  Box box{s.lx, s.ly, true};
  Particles p;
  p.reserve(s.grains + 1);
  const long max_attempts = 2000 * s.grains + 100000;
  long attempts = 0;
  while (static_cast<long>(p.size()) < s.grains) {
    if (++attempts > max_attempts)
      throw Error("could not place " + std::to_string(s.grains) +
                  " grains without overlaps; lower 'fill_fraction'");
    const double r = 0.5 * (0.9 + 0.2 * u01(rng));
    const Vec3 x(s.lx * u01(rng), s.ly * u01(rng), r + (top - 2 * r) * u01(rng));
    if (R > 0 && box.min_image(x - intruder).norm() < R + r) continue;
    const int ix = std::min(nx - 1, static_cast<int>(x.x() / cx));
    const int iy = std::min(ny - 1, static_cast<int>(x.y() / cy));
    const int iz = std::min(nz - 1, static_cast<int>(x.z() / cz));
    bool free = true;
    for (int dz = -1; dz <= 1 && free; ++dz) {
      const int kz = iz + dz;
      if (kz < 0 || kz >= nz) continue;
      for (int dy = -1; dy <= 1 && free; ++dy)
        for (int dx = -1; dx <= 1 && free; ++dx) {
          const int kx = ((ix + dx) % nx + nx) % nx, ky = ((iy + dy) % ny + ny) % ny;
          for (int j : cells[(static_cast<std::size_t>(kz) * ny + ky) * nx + kx])
            if (box.min_image(x - p.x[j]).norm() < r + p.radius[j]) {
              free = false;
              break;
            }
        }
    }
    if (!free) continue;
    cells[(static_cast<std::size_t>(iz) * ny + iy) * nx + ix].push_back(static_cast<int>(p.size()));
    p.add(x, r, Species::Mobile);
  }
  // Order grains by coarse cell, bottom up: neighbours in space become neighbours in memory.
  std::vector<std::size_t> order(p.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto key = [&](std::size_t i) {
    const long kz = static_cast<long>(p.x[i].z() / 2.0), ky = static_cast<long>(p.x[i].y() / 2.0);
    return std::make_tuple(kz, ky, p.x[i].x());
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  Particles sorted;
  sorted.reserve(p.size() + 1);
  for (std::size_t i : order) sorted.add(p.x[i], p.radius[i], Species::Mobile);
  return sorted;
}

Bed pour(const PourSpec& s, bool show_progress, const PourCheckpoints& checkpoints) {
  s.validate();
  Bed bed;
  bed.box = Box{s.lx, s.ly, true};
  bed.contact = s.contact;
  bed.requested_depth = s.depth;
  const bool has_intruder = s.intruder_diameter > 0;
  double z0 = NAN;
  if (has_intruder) z0 = std::isnan(s.depth) ? s.intruder_z : intruder_height_for_depth(s);
  if (has_intruder && !(z0 - 0.5 * s.intruder_diameter >= s.base_height))
    throw Error(
        "'intruder_z' = " + std::to_string(z0) + " puts the intruder into the base; it " +
        "must be >= D/2 + base_height = " + std::to_string(0.5 * s.intruder_diameter + s.base_height));
  double column_top = 0;
  Particles p = place_grains(s, has_intruder ? z0 : 0.0, &column_top);
  if (has_intruder) {
    bed.intruder = static_cast<int>(
        p.add(Vec3(s.intruder_x, s.intruder_y, z0), 0.5 * s.intruder_diameter, Species::Intruder));
  }
  Settings settings;
  settings.dt = s.dt;
  settings.skin = s.skin;
  Simulation sim(std::move(p), bed.box, s.contact, settings);
  bed.dt = sim.dt();
  const long chunk = std::max(1L, std::lround(s.check_interval / sim.dt()));
  // Grains start at rest: the kinetic energy is tiny before they have fallen. No threshold
  // stop before the top of the column could have fallen to the wall (t = sqrt(2 z_top / g)).
  const double min_settle_time = std::min(s.max_settle_time, std::sqrt(2.0 * column_top));
  const long grains = s.grains;
  GuardLimits limits;
  limits.max_overlap = s.max_overlap;
  limits.z_max = column_top + 10.0;  // the grains start at rest below column_top
  const PourState* resume = checkpoints.resume_from;
  if (resume) {
    if (resume->state.particles.size() != sim.particles().size() || resume->state.steps % chunk != 0)
      throw Error("the pour checkpoint does not fit this pour (particle count or check interval)");
    sim.restore(resume->state);
  } else {
    sim.setup();
  }
  RunGuard guard(limits, resume ? resume->energy_start : sim.energy().total());
  if (resume) guard.restore(resume->max_overlap_seen, resume->grains_lost);
  const bool dump = checkpoints.frame_every > 0 && checkpoints.frame;
  long frames = resume ? resume->frames : 0;
  if (dump && frames == 0) {
    checkpoints.frame(sim);
    ++frames;
  }
  const double t0 = omp_get_wtime();
  const long steps0 = sim.steps_done();
  bed.stop_reason = "max_time";
  while (true) {
    sim.run(chunk);
    // A failure stops the pour here, before a checkpoint could save it.
    const std::string why = guard.check(sim, 0.0);
    if (!why.empty()) throw Error("the pour stopped: " + why + ". The last good checkpoint, if any, is kept");
    if (dump && (sim.steps_done() / chunk) % checkpoints.frame_every == 0) {
      checkpoints.frame(sim);
      ++frames;
    }
    const Energy e = sim.energy();
    bed.kinetic_energy = (e.kinetic + e.rotational) / grains;
    if (show_progress) {
      const double elapsed = omp_get_wtime() - t0;
      std::fprintf(stderr,
                   "pour: t = %.1f of at most %.0f sqrt(d/g), kinetic energy per grain %.3g "
                   "(target %.3g), %.3g particle-steps/s, elapsed %.0f s\n",
                   sim.time(), s.max_settle_time, bed.kinetic_energy, s.ke_threshold,
                   sim.particles().size() * static_cast<double>(sim.steps_done() - steps0) / elapsed,
                   elapsed);
    }
    if (!std::isfinite(bed.kinetic_energy))
      throw Error("the pour blew up at t = " + std::to_string(sim.time()) +
                  ": non-finite kinetic energy; the time step is too large for the stiffness");
    if (bed.kinetic_energy < s.ke_threshold && sim.time() >= min_settle_time) {
      bed.stop_reason = "threshold";
      break;
    }
    if (sim.time() >= s.max_settle_time) break;
    if (checkpoints.every > 0 && (sim.steps_done() / chunk) % checkpoints.every == 0 && checkpoints.save) {
      sim.rebuild_lists();
      checkpoints.save(PourState{sim.state(), guard.energy_start(), guard.max_overlap_seen(),
                                 guard.grains_lost(), sim.dt(), frames});
    }
  }
  bed.settle_time = sim.time();
  {
    const Particles& q = sim.particles();
    long lost = 0;
    for (std::size_t i = 0; i < q.size(); ++i)
      if (q.species[i] == Species::Mobile && (!q.x[i].allFinite() || q.x[i].z() < 0)) ++lost;
    const Energy e = sim.energy();
    const double elapsed = omp_get_wtime() - t0;
    std::ostringstream report;
    report << "sanity: grains lost " << lost << " of " << grains << "; largest overlap "
           << sim.contacts().max_overlap(q, bed.box) << " d; energy of the grains: kinetic "
           << e.kinetic + e.rotational << ", gravitational " << e.potential << ", elastic " << e.elastic
           << " (rho g d^4); "
           << q.size() * static_cast<double>(sim.steps_done() - steps0) / std::max(elapsed, 1e-9)
           << " particle-steps/s\n";
    bed.sanity = report.str();
  }
  sim.particles().freeze_below(s.base_height);
  sim.rebuild_lists();  // frozen pairs leave the lists; the state is saved from a fresh build
  bed.state = sim.state();
  bed.state.steps = 0;  // a pull starts its own clock
  bed.profile = measure_bed(bed.state.particles, bed.box);
  bed.surface_height = bed.profile.surface_height;
  if (has_intruder) {
    bed.depth = bed.surface_height - bed.state.particles.x[bed.intruder].z();
    if (!std::isnan(s.depth) && std::abs(bed.depth - s.depth) > 1.0)
      std::fprintf(stderr,
                   "pour: warning: the intruder ended at depth %.3f d, %.2f d from the requested %.3f d "
                   "(bulk packing fraction %.3f, packing_estimate %.3f)\n",
                   bed.depth, bed.depth - s.depth, s.depth, bed.profile.bulk_packing_fraction,
                   assumed_packing(s));
    if (bed.depth < 0.5 * s.intruder_diameter)
      std::fprintf(stderr, "pour: warning: the intruder is not buried (depth %.3f d < D/2)\n", bed.depth);
  }
  return bed;
}

}  // namespace granudrag
