#include "protocol/placement.hpp"

#include <omp.h>

#include <algorithm>
#include <sstream>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "protocol/bed_profile.hpp"
#include "protocol/run_report.hpp"

namespace granudrag {

const KeyTable<PlacementSpec>& placement_keys() {
  static const KeyTable<PlacementSpec> keys = {
      Key::number("intruder_diameter")
          .unit("d")
          .above(0)
          .help("D of the intruder placed")
          .field(&PlacementSpec::intruder_diameter),
      Key::number("intruder_x").unit("d").at_least(0).help("intruder centre x (default lx/2)"),
      Key::number("intruder_y").unit("d").at_least(0).help("intruder centre y (default ly/2)"),
      Key::number("depth")
          .unit("d")
          .above(0)
          .help("depth h of the intruder centre below the source bed's free surface (required)")
          .field(&PlacementSpec::depth),
      // Read by the command: its default is the source bed's (place_command.cpp).
      Key::number("ke_threshold")
          .unit("rho g d^4")
          .above(0)
          .help("settled again when the mean kinetic energy per grain is below (default: the source's pour's "
                "ke_threshold; 1e-7 if it records none)"),
      Key::number("min_settle_time")
          .unit("sqrt(d/g)")
          .at_least(0)
          .help("settle at least this long before the threshold may stop the settling")
          .field(&PlacementSpec::min_settle_time),
      Key::number("max_settle_time")
          .unit("sqrt(d/g)")
          .above(0)
          .help("stop settling after this time anyway (recorded as stop_reason max_time)")
          .field(&PlacementSpec::max_settle_time),
      Key::number("check_interval")
          .unit("sqrt(d/g)")
          .above(0)
          .help("time between kinetic-energy checks")
          .field(&PlacementSpec::check_interval),
      Key::number("settle_damping")
          .unit("sqrt(g/d)")
          .at_least(0)
          .help("a viscous drag -settle_damping m v on every grain while it settles, as the pour's; 0: off")
          .field(&PlacementSpec::settle_damping),
      Key::number("source_ke_factor")
          .above(0)
          .help("a source bed whose pour ran out of time (stop_reason max_time) with its grains' kinetic "
                "energy "
                "per grain above this many ke_threshold is refused as unsettled")
          .field(&PlacementSpec::source_ke_factor),
      Key(skin_key()).field(&PlacementSpec::skin),
      Key(max_overlap_key()).field(&PlacementSpec::max_overlap),
  };
  return keys;
}

void PlacementSpec::validate() const {
  placement_keys().check(*this, "placement settings");
  if (std::isnan(depth))
    throw Error("give 'depth', the intruder centre's depth below the bed's free surface");
  if (!(min_settle_time <= max_settle_time))
    throw Error("'min_settle_time' = " + std::to_string(min_settle_time) +
                " is above 'max_settle_time' = " + std::to_string(max_settle_time));
}

namespace {

// Every pair of kept bodies keeps its history, renumbered; the others are dropped.
std::vector<PairHistory> renumbered(const std::vector<PairHistory>& pairs,
                                    const std::vector<long>& new_index) {
  std::vector<PairHistory> out;
  out.reserve(pairs.size());
  for (const PairHistory& h : pairs) {
    const long i = new_index[h.i], j = new_index[h.j];
    if (i >= 0 && j >= 0) out.push_back({static_cast<int>(i), static_cast<int>(j), h.shear});
  }
  return out;
}

}  // namespace

Bed placed_column(const Bed& source, const PlacementSpec& spec, PlacementRecord* record) {
  spec.validate();
  const Particles& p = source.state.particles;
  if (source.intruder >= 0)
    throw Error("the source bed already has an intruder: place into a bed poured with intruder_diameter 0");
  const double R = 0.5 * spec.intruder_diameter;
  if (!(spec.intruder_diameter <= 0.5 * std::min(source.box.lx, source.box.ly))) {
    std::ostringstream msg;
    msg << "'intruder_diameter' = " << spec.intruder_diameter << " does not fit the box " << source.box.lx
        << " x " << source.box.ly << " d: it must be at most half the box's narrower side ("
        << 0.5 * std::min(source.box.lx, source.box.ly) << " d), or it meets its periodic image";
    throw Error(msg.str());
  }
  const double limit = spec.source_ke_factor * spec.ke_threshold;
  if (source.stop_reason != "threshold" && source.kinetic_energy > limit) {
    std::ostringstream msg;
    msg << "the source bed never settled: its grains' kinetic energy was " << source.kinetic_energy
        << " per grain when its pour stopped (by " << source.stop_reason << "), above source_ke_factor x "
        << "ke_threshold = " << limit << "; pour it longer (max_settle_time) or raise 'ke_threshold'";
    throw Error(msg.str());
  }
  const double x = std::isnan(spec.intruder_x) ? 0.5 * source.box.lx : spec.intruder_x;
  const double y = std::isnan(spec.intruder_y) ? 0.5 * source.box.ly : spec.intruder_y;
  if (!(x < source.box.lx) || !(y < source.box.ly))
    throw Error("'intruder_x', 'intruder_y' = " + std::to_string(x) + ", " + std::to_string(y) +
                " is outside the box: 0 <= x < lx, 0 <= y < ly");
  const double z = source.surface_height - spec.depth;
  double base_top = 0;  // the highest point of the frozen base
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.species[i] == Species::Frozen) base_top = std::max(base_top, p.x[i].z() + p.radius[i]);
  if (z - R < base_top) {
    std::ostringstream msg;
    msg << "'depth' = " << spec.depth << " is deeper than the bed: its surface is at "
        << source.surface_height << " d and its frozen base reaches " << base_top
        << " d, so an intruder of D = " << spec.intruder_diameter
        << " fits for depth <= " << source.surface_height - base_top - R;
    throw Error(msg.str());
  }
  const Vec3 centre(x, y, z);
  std::vector<long> new_index(p.size(), -1);
  Particles kept;
  kept.reserve(p.size() + 1);
  PlacementRecord rec;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (source.box.min_image(p.x[i] - centre).norm() < R + p.radius[i]) {
      rec.removed.push_back(static_cast<long>(i));
      continue;
    }
    new_index[i] = static_cast<long>(kept.size());
    kept.add(p.x[i], p.radius[i], p.species[i]);
    const std::size_t k = kept.size() - 1;
    kept.v[k] = p.v[i];
    kept.omega[k] = p.omega[i];
  }
  Bed bed = source;
  bed.intruder = static_cast<int>(kept.add(centre, R, Species::Intruder));
  bed.state.particles = std::move(kept);
  bed.state.pair_history = renumbered(source.state.pair_history, new_index);
  if (source.state.wall_history.size() == p.size()) {
    bed.state.wall_history.assign(bed.state.particles.size(), Vec3::Zero());
    for (std::size_t i = 0; i < p.size(); ++i)
      if (new_index[i] >= 0) bed.state.wall_history[new_index[i]] = source.state.wall_history[i];
  } else {
    bed.state.wall_history.clear();
  }
  bed.state.steps = 0;
  bed.requested_depth = spec.depth;
  rec.source_surface_height = source.surface_height;
  rec.source_kinetic_energy = source.kinetic_energy;
  rec.intruder_z = z;
  if (record) *record = std::move(rec);
  return bed;
}

namespace {
Settings placement_settings(const Bed& bed, const PlacementSpec& spec) {
  Settings s;
  s.dt = bed.dt;
  s.skin = spec.skin;
  s.viscous_damping = spec.settle_damping;
  return s;
}
}  // namespace

Placement::Placement(const Bed& placed, const PlacementSpec& spec)
    : spec_(spec),
      bed_(placed),
      sim_(placed.state.particles, placed.box, placed.contact, placement_settings(placed, spec)),
      guard_(GuardLimits{}, 0.0) {
  sim_.restore(placed.state);
  energy_start_ = sim_.energy().total();
  GuardLimits limits;
  limits.max_overlap = spec_.max_overlap;
  limits.z_max = placed.surface_height + 10.0;
  guard_ = RunGuard(limits, energy_start_);
}

void Placement::run(bool show_progress) {
  const long chunk = std::max(1L, std::lround(spec_.check_interval / sim_.dt()));
  const long max_steps = static_cast<long>(std::ceil(spec_.max_settle_time / (chunk * sim_.dt()))) * chunk;
  Progress progress("place", max_steps, 0);
  const double n = static_cast<double>(sim_.particles().size());
  const double mobile = static_cast<double>(sim_.particles().count(Species::Mobile));
  const double t0 = omp_get_wtime();
  sim_.timers().reset();
  std::string stop = "max_time";
  double ke = NAN;
  while (sim_.steps_done() < max_steps) {
    sim_.run(chunk);
    const std::string why = guard_.check(sim_, 0.0);
    if (!why.empty()) throw Error("the placement's settling stopped: " + why);
    const Energy e = sim_.energy();
    ke = (e.kinetic + e.rotational) / mobile;
    if (!std::isfinite(ke))
      throw Error("the placement's settling blew up at t = " + std::to_string(sim_.time()) +
                  ": non-finite kinetic energy");
    if (show_progress) progress.update(sim_.steps_done(), n, "particle-steps");
    if (ke < spec_.ke_threshold && sim_.time() >= spec_.min_settle_time) {
      stop = "threshold";
      break;
    }
  }
  loop_seconds_ = omp_get_wtime() - t0;
  loop_steps_ = sim_.steps_done();
  SanityFigures f;
  f.grains = static_cast<long>(mobile);
  f.grains_lost = guard_.grains_lost();
  f.largest_overlap = guard_.max_overlap_seen();
  f.energy_start = energy_start_;
  f.energy_end = sim_.energy().total();
  f.particle_steps_per_second = n * loop_steps_ / std::max(loop_seconds_, 1e-9);
  sim_.rebuild_lists();
  bed_.state = sim_.state();
  bed_.state.steps = 0;  // a pull starts its own clock
  bed_.stop_reason = stop;
  bed_.kinetic_energy = ke;
  bed_.settle_time = sim_.time();
  bed_.sanity = sanity_line(f);
  bed_.profile = measure_bed(bed_.state.particles, bed_.box);
  bed_.surface_height = bed_.profile.surface_height;
  bed_.depth = bed_.surface_height - bed_.state.particles.x[bed_.intruder].z();
}

std::string Placement::timing_report() const {
  return timing_line(sim_.timers(), static_cast<double>(sim_.particles().size()), loop_steps_, loop_seconds_);
}

}  // namespace granudrag
