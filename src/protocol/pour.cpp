#include "protocol/pour.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <sstream>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "engine/run_guard.hpp"
#include "protocol/run_report.hpp"

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

struct Pour::Column {
  Particles particles;  // the grains placed, the intruder last
  double top = 0;       // of the loose column
  int intruder = -1;
};

Pour::Column Pour::loose_column(const PourSpec& s) {
  s.validate();
  const bool has_intruder = s.intruder_diameter > 0;
  double z0 = NAN;
  if (has_intruder) z0 = std::isnan(s.depth) ? s.intruder_z : intruder_height_for_depth(s);
  if (has_intruder && !(z0 - 0.5 * s.intruder_diameter >= s.base_height))
    throw Error(
        "'intruder_z' = " + std::to_string(z0) + " puts the intruder into the base; it " +
        "must be >= D/2 + base_height = " + std::to_string(0.5 * s.intruder_diameter + s.base_height));
  Column c;
  c.particles = place_grains(s, has_intruder ? z0 : 0.0, &c.top);
  if (has_intruder)
    c.intruder = static_cast<int>(
        c.particles.add(Vec3(s.intruder_x, s.intruder_y, z0), 0.5 * s.intruder_diameter, Species::Intruder));
  return c;
}

namespace {

// Grains start at rest: the kinetic energy is tiny before they have fallen. Neither the threshold
// stop nor the settling damping comes before the top of the column could have fallen to the
// wall (t = sqrt(2 z_top / g)).
double fallen_time(const PourSpec& s, double column_top) {
  return std::min(s.max_settle_time, std::sqrt(2.0 * column_top));
}

Settings pour_settings(const PourSpec& s, double column_top) {
  Settings settings;
  settings.dt = std::isnan(s.dt) ? 0.0 : s.dt;  // 0: Simulation derives it
  settings.skin = s.skin;
  settings.viscous_damping = s.settle_damping;
  settings.viscous_from = fallen_time(s, column_top);
  return settings;
}

}  // namespace

Pour::Pour(const PourSpec& spec) : Pour(spec, loose_column(spec), nullptr) {}

Pour::Pour(const PourSpec& spec, const Simulation::State& state, PourRecord record)
    : Pour(spec, loose_column(spec), &state) {
  record_ = std::move(record);
  record_.stop_reason.clear();  // a checkpoint is taken only while the pour runs
  guard_ = RunGuard(guard_.limits(), record_.energy_start);
  guard_.restore(record_.max_overlap, record_.grains_lost);
}

Pour::Pour(const PourSpec& spec, Column column, const Simulation::State* resume)
    : spec_(spec),
      sim_(std::move(column.particles), Box{spec.lx, spec.ly, true}, spec.contact,
           pour_settings(spec, column.top)),
      guard_(GuardLimits{}, 0.0),
      column_top_(column.top) {
  bed_.box = Box{spec_.lx, spec_.ly, true};
  bed_.contact = spec_.contact;
  bed_.requested_depth = spec_.depth;
  bed_.intruder = column.intruder;
  bed_.dt = sim_.dt();
  chunk_ = std::max(1L, std::lround(spec_.check_interval / sim_.dt()));
  // The loop ends at the first check at or past max_settle_time, at time() = steps * dt.
  auto time_at = [&](long checks) { return static_cast<double>(checks * chunk_) * sim_.dt(); };
  long checks = std::max(1L, static_cast<long>(std::ceil(spec_.max_settle_time / time_at(1))));
  while (checks > 1 && time_at(checks - 1) >= spec_.max_settle_time) --checks;
  while (time_at(checks) < spec_.max_settle_time) ++checks;
  max_steps_ = checks * chunk_;
  min_settle_time_ = fallen_time(spec_, column_top_);
  GuardLimits limits;
  limits.max_overlap = spec_.max_overlap;
  limits.z_max = column_top_ + 10.0;  // the grains start at rest below column_top
  if (resume) {
    if (resume->particles.size() != sim_.particles().size() || resume->steps % chunk_ != 0)
      throw Error("the pour checkpoint does not fit this pour (particle count or check interval)");
    sim_.restore(*resume);
  } else {
    sim_.setup();
    record_.energy_start = sim_.energy().total();
  }
  guard_ = RunGuard(limits, record_.energy_start);
}

void Pour::run(bool show_progress, const std::function<void(const Pour&)>& on_checkpoint,
               const std::function<void(const Pour&)>& on_frame) {
  if (finished()) return;
  Progress progress("pour", max_steps_, sim_.steps_done());
  const double n = static_cast<double>(sim_.particles().size());
  Timers& timers = sim_.timers();
  timers.reset();
  const long first_step = sim_.steps_done();
  const double t0 = omp_get_wtime();
  const bool dump = spec_.dump_every > 0 && on_frame;
  auto frame = [&] {
    timers.start();
    on_frame(*this);
    ++record_.frames;
    timers.stamp(Phase::IO);
  };
  if (dump && record_.frames == 0) frame();
  while (true) {
    sim_.run(chunk_);
    // A failure stops the pour here, before a checkpoint could save it.
    const std::string why = guard_.check(sim_, 0.0);
    record_.max_overlap = guard_.max_overlap_seen();
    record_.grains_lost = guard_.grains_lost();
    if (!why.empty()) throw Error("the pour stopped: " + why + ". The last good checkpoint, if any, is kept");
    const Energy e = sim_.energy();
    record_.kinetic_energy = (e.kinetic + e.rotational) / spec_.grains;
    timers.stamp(Phase::Observables);
    const long checks = sim_.steps_done() / chunk_;
    if (dump && checks % spec_.dump_every == 0) frame();
    if (show_progress) progress.update(sim_.steps_done(), n, "particle-steps");
    if (!std::isfinite(record_.kinetic_energy))
      throw Error("the pour blew up at t = " + std::to_string(sim_.time()) +
                  ": non-finite kinetic energy; the time step is too large for the stiffness");
    if (record_.kinetic_energy < spec_.ke_threshold && sim_.time() >= min_settle_time_) {
      record_.stop_reason = "threshold";
      break;
    }
    if (sim_.time() >= spec_.max_settle_time) {
      record_.stop_reason = "max_time";
      break;
    }
    if (spec_.checkpoint_every > 0 && checks % spec_.checkpoint_every == 0 && on_checkpoint) {
      sim_.rebuild_lists();
      on_checkpoint(*this);
      timers.stamp(Phase::IO);
    }
  }
  loop_seconds_ = omp_get_wtime() - t0;
  loop_steps_ = sim_.steps_done() - first_step;
  finish();
}

void Pour::finish() {
  const Particles& q = sim_.particles();
  end_lost_ = 0;
  for (std::size_t i = 0; i < q.size(); ++i)
    if (q.species[i] == Species::Mobile && (!q.x[i].allFinite() || q.x[i].z() < 0)) ++end_lost_;
  end_energy_ = sim_.energy().total();
  bed_.stop_reason = record_.stop_reason;
  bed_.kinetic_energy = record_.kinetic_energy;
  bed_.settle_time = sim_.time();
  bed_.sanity = sanity_report(loop_seconds_);
  sim_.particles().freeze_below(spec_.base_height);
  sim_.rebuild_lists();  // frozen pairs leave the lists; the state is saved from a fresh build
  bed_.state = sim_.state();
  bed_.state.steps = 0;  // a pull starts its own clock
  bed_.profile = measure_bed(bed_.state.particles, bed_.box);
  bed_.surface_height = bed_.profile.surface_height;
  if (bed_.intruder < 0) return;
  const PourSpec& s = spec_;
  bed_.depth = bed_.surface_height - bed_.state.particles.x[bed_.intruder].z();
  if (!std::isnan(s.depth) && std::abs(bed_.depth - s.depth) > 1.0)
    std::fprintf(stderr,
                 "pour: warning: the intruder ended at depth %.3f d, %.2f d from the requested %.3f d "
                 "(bulk packing fraction %.3f, packing_estimate %.3f)\n",
                 bed_.depth, bed_.depth - s.depth, s.depth, bed_.profile.bulk_packing_fraction,
                 assumed_packing(s));
  if (bed_.depth < 0.5 * s.intruder_diameter)
    std::fprintf(stderr, "pour: warning: the intruder is not buried (depth %.3f d < D/2)\n", bed_.depth);
}

std::string Pour::sanity_report(double wall_seconds) const {
  SanityFigures f;
  f.grains_lost = end_lost_;
  f.grains = spec_.grains;
  f.largest_overlap = record_.max_overlap;
  f.energy_start = record_.energy_start;
  f.energy_end = end_energy_;
  // This run's steps: a resumed pour did the others in another process.
  f.particle_steps_per_second =
      static_cast<double>(sim_.particles().size()) * loop_steps_ / std::max(wall_seconds, 1e-9);
  return sanity_line(f);
}

std::string Pour::timing_report() const {
  return timing_line(sim_.timers(), static_cast<double>(sim_.particles().size()), loop_steps_, loop_seconds_);
}

Bed pour(const PourSpec& spec, bool show_progress) {
  Pour p(spec);
  p.run(show_progress);
  return p.result();
}

}  // namespace granudrag
