#include "io/run_files.hpp"

#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "io/h5_file.hpp"
#include "io/xdmf.hpp"

namespace granudrag {

namespace {

const char* kParticles = "/particles/all";

void write_header(h5::File& f, const std::string& format, const std::string& yaml) {
  h5::write_h5md_header(f, std::string(GRANUDRAG_VERSION) + " (" + GRANUDRAG_COMMIT + ")");
  f.set_attr("/granudrag", "format", format);
  f.set_attr("/granudrag", "version", kFileVersion);
  f.set_attr("/granudrag", "code_version", std::string(GRANUDRAG_VERSION));
  f.set_attr("/granudrag", "commit", std::string(GRANUDRAG_COMMIT));
  f.set_attr("/parameters", "yaml", yaml);
}

void check_header(const h5::File& f, const std::string& path, const std::string& format) {
  if (!f.has_attr("/granudrag", "format"))
    throw Error("'" + path + "' is not a granudrag file (no /granudrag format attribute)");
  const std::string got = f.get_attr_string("/granudrag", "format");
  if (got != format) throw Error("'" + path + "' is a " + got + " file, not a " + format + " file");
  const std::int64_t version = f.get_attr_int64("/granudrag", "version");
  if (version != kFileVersion)
    throw Error("'" + path + "' has format version " + std::to_string(version) +
                "; this granudrag reads version " + std::to_string(kFileVersion) +
                ": re-create it with this version");
}

void write_state(h5::File& f, const Simulation::State& s, double dt) {
  const Particles& p = s.particles;
  // One frame: each element gets the H5MD step and time beside its value.
  for (const char* element :
       {"position", "velocity", "angular_velocity", "force", "torque", "radius", "species"}) {
    f.write(std::string(kParticles) + "/" + element + "/step", std::vector<std::int64_t>{s.steps});
    f.write(std::string(kParticles) + "/" + element + "/time", std::vector<double>{s.steps * dt});
  }
  f.write_rows(std::string(kParticles) + "/position/value", p.x);
  f.write_rows(std::string(kParticles) + "/velocity/value", p.v);
  f.write_rows(std::string(kParticles) + "/angular_velocity/value", p.omega);
  f.write_rows(std::string(kParticles) + "/force/value", p.f);
  f.write_rows(std::string(kParticles) + "/torque/value", p.torque);
  f.write(std::string(kParticles) + "/radius/value", p.radius);
  std::vector<std::uint8_t> species(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) species[i] = static_cast<std::uint8_t>(p.species[i]);
  f.write(std::string(kParticles) + "/species/value", species);
  f.set_attr(std::string(kParticles) + "/species", "meaning",
             std::string("0 mobile grain, 1 frozen base grain, 2 intruder"));
  std::vector<std::int64_t> pairs;
  std::vector<Vec3> shear;
  for (const PairHistory& h : s.pair_history) {
    pairs.push_back(h.i);
    pairs.push_back(h.j);
    shear.push_back(h.shear);
  }
  f.write("/contacts/pairs", pairs);
  f.write_rows("/contacts/shear", shear);
  f.set_attr("/contacts", "convention",
             std::string("pairs (i, j), i < j; shear: tangential spring seen from i"));
  std::vector<Vec3> wall = s.wall_history;
  wall.resize(p.size(), Vec3::Zero());
  f.write_rows("/contacts/wall_shear", wall);
  f.set_attr("/contacts", "step", static_cast<std::int64_t>(s.steps));
}

Simulation::State read_state(const h5::File& f) {
  Simulation::State s;
  const std::vector<Vec3> x = f.read_vec3(std::string(kParticles) + "/position/value");
  const std::vector<double> radius = f.read_doubles(std::string(kParticles) + "/radius/value");
  const std::vector<std::uint8_t> species = f.read_uint8(std::string(kParticles) + "/species/value");
  if (radius.size() != x.size() || species.size() != x.size())
    throw Error("particle arrays of different lengths in the file");
  Particles& p = s.particles;
  p.reserve(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (species[i] > 2)
      throw Error("unknown species " + std::to_string(species[i]) + " of particle " + std::to_string(i));
    p.add(x[i], radius[i], static_cast<Species>(species[i]));
  }
  p.v = f.read_vec3(std::string(kParticles) + "/velocity/value");
  p.omega = f.read_vec3(std::string(kParticles) + "/angular_velocity/value");
  p.f = f.read_vec3(std::string(kParticles) + "/force/value");
  p.torque = f.read_vec3(std::string(kParticles) + "/torque/value");
  if (p.v.size() != x.size() || p.omega.size() != x.size() || p.f.size() != x.size() ||
      p.torque.size() != x.size())
    throw Error("particle arrays of different lengths in the file");
  const std::vector<std::int64_t> pairs = f.read_int64("/contacts/pairs");
  const std::vector<Vec3> shear = f.read_vec3("/contacts/shear");
  if (pairs.size() != 2 * shear.size()) throw Error("/contacts/pairs and /contacts/shear disagree in length");
  for (std::size_t k = 0; k < shear.size(); ++k) {
    const std::int64_t i = pairs[2 * k], j = pairs[2 * k + 1];
    if (i < 0 || j <= i || j >= static_cast<std::int64_t>(x.size()))
      throw Error("bad contact pair in /contacts/pairs");
    s.pair_history.push_back({static_cast<int>(i), static_cast<int>(j), shear[k]});
  }
  s.wall_history = f.read_vec3("/contacts/wall_shear");
  s.steps = f.get_attr_int64("/contacts", "step");
  return s;
}

void write_bed_body(h5::File& f, const Bed& bed) {
  write_state(f, bed.state, bed.dt);
  f.set_attr("/box", "lx", bed.box.lx);
  f.set_attr("/box", "ly", bed.box.ly);
  f.set_attr("/box", "wall", static_cast<std::int64_t>(bed.box.wall));
  f.set_attr("/contact", "kn", bed.contact.kn);
  f.set_attr("/contact", "kt", bed.contact.kt);
  f.set_attr("/contact", "gamman", bed.contact.gamman);
  f.set_attr("/contact", "gammat", bed.contact.gammat);
  f.set_attr("/contact", "mu", bed.contact.mu);
  f.set_attr("/contact", "dt", bed.dt);
  f.set_attr("/bed", "intruder", static_cast<std::int64_t>(bed.intruder));
  f.set_attr("/bed", "surface_height", bed.surface_height);
  f.set_attr(
      "/bed", "surface_definition",
      std::string("height where the packing fraction of the grains (slabs of 0.1 d) falls to half its bulk "
                  "value; bulk = median over slabs from 2 d above the wall to 4 d below the bed top (highest "
                  "slab denser than a tenth of the densest), slabs cut by the intruder left out"));
  f.set_attr("/bed", "depth", bed.depth);
  f.set_attr("/bed", "requested_depth", bed.requested_depth);
  f.set_attr("/bed", "stop_reason", bed.stop_reason);
  f.set_attr("/bed", "kinetic_energy_per_grain", bed.kinetic_energy);
  f.set_attr("/bed", "settle_time", bed.settle_time);
  f.set_attr("/bed", "sanity", bed.sanity);
  f.set_attr("/bed", "bulk_packing_fraction", bed.profile.bulk_packing_fraction);
  f.write("/bed/profile/z", bed.profile.z);
  f.write("/bed/profile/packing_fraction", bed.profile.packing_fraction);
}

Bed read_bed_body(const h5::File& f) {
  Bed bed;
  bed.state = read_state(f);
  bed.box.lx = f.get_attr_double("/box", "lx");
  bed.box.ly = f.get_attr_double("/box", "ly");
  bed.box.wall = f.get_attr_int64("/box", "wall") != 0;
  bed.contact.kn = f.get_attr_double("/contact", "kn");
  bed.contact.kt = f.get_attr_double("/contact", "kt");
  bed.contact.gamman = f.get_attr_double("/contact", "gamman");
  bed.contact.gammat = f.get_attr_double("/contact", "gammat");
  bed.contact.mu = f.get_attr_double("/contact", "mu");
  bed.dt = f.get_attr_double("/contact", "dt");
  bed.intruder = static_cast<int>(f.get_attr_int64("/bed", "intruder"));
  const Particles& p = bed.state.particles;
  if (bed.intruder >= static_cast<int>(p.size()) || bed.intruder < -1 ||
      (bed.intruder >= 0 && p.species[bed.intruder] != Species::Intruder))
    throw Error("/bed/intruder = " + std::to_string(bed.intruder) + " is not the index of an intruder");
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!(p.radius[i] > 0) || !std::isfinite(p.radius[i]) || !p.x[i].allFinite())
      throw Error("particle " + std::to_string(i) + " has a bad radius or position");
  if (!(bed.box.lx > 0) || !(bed.box.ly > 0) || !(bed.dt > 0))
    throw Error("bad box or time step under /box, /contact");
  bed.surface_height = f.get_attr_double("/bed", "surface_height");
  bed.depth = f.get_attr_double("/bed", "depth");
  bed.requested_depth = f.get_attr_double("/bed", "requested_depth");
  bed.stop_reason = f.get_attr_string("/bed", "stop_reason");
  bed.kinetic_energy = f.get_attr_double("/bed", "kinetic_energy_per_grain");
  bed.settle_time = f.get_attr_double("/bed", "settle_time");
  if (f.has_attr("/bed", "sanity")) bed.sanity = f.get_attr_string("/bed", "sanity");  // absent if imported
  bed.profile.bulk_packing_fraction = f.get_attr_double("/bed", "bulk_packing_fraction");
  bed.profile.z = f.read_doubles("/bed/profile/z");
  bed.profile.packing_fraction = f.read_doubles("/bed/profile/packing_fraction");
  bed.profile.surface_height = bed.surface_height;
  return bed;
}

// Snapshots k = 0, 1, ... as groups <prefix><k> holding dx, dz, vx, vz and the time.
void write_snapshots(h5::File& f, const std::string& prefix, const std::vector<Snapshot>& snapshots) {
  for (std::size_t k = 0; k < snapshots.size(); ++k) {
    const std::string g = prefix + std::to_string(k);
    f.set_attr(g, "time", snapshots[k].time);
    f.write(g + "/dx", snapshots[k].dx);
    f.write(g + "/dz", snapshots[k].dz);
    f.write(g + "/vx", snapshots[k].vx);
    f.write(g + "/vz", snapshots[k].vz);
  }
}

}  // namespace

void save_bed(const std::string& path, const Bed& bed, const std::string& yaml) {
  h5::File f = h5::File::create(path);
  write_header(f, "granudrag-bed", yaml);
  write_bed_body(f, bed);
  f.commit();
}

Bed load_bed(const std::string& path, std::string* yaml) {
  const h5::File f = h5::File::open(path);
  check_header(f, path, "granudrag-bed");
  try {
    Bed bed = read_bed_body(f);
    if (yaml) *yaml = f.get_attr_string("/parameters", "yaml");
    return bed;
  } catch (const Error& e) {
    throw Error("bed file '" + path + "' is damaged: " + e.what());
  }
}

std::string bed_fingerprint(const Bed& bed) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the bytes
  auto mix = [&h](const void* data, std::size_t bytes) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) h = (h ^ b[k]) * 1099511628211ull;
  };
  const Particles& p = bed.state.particles;
  mix(p.x.data(), p.x.size() * sizeof(Vec3));
  mix(p.radius.data(), p.radius.size() * sizeof(double));
  mix(p.species.data(), p.species.size() * sizeof(Species));
  char text[32];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

void save_checkpoint(const std::string& path, const Pull& pull, const std::string& yaml,
                     const std::string& identity) {
  h5::File f = h5::File::create(path);
  write_header(f, "granudrag-checkpoint", yaml);
  f.set_attr("/pull", "identity", identity);
  Bed bed = pull.bed();
  bed.state = pull.state();
  write_bed_body(f, bed);
  const PullRecord& r = pull.record();
  f.set_attr("/pull", "samples_per_interval", static_cast<std::int64_t>(r.samples_per_interval));
  f.set_attr("/pull", "total_steps", static_cast<std::int64_t>(r.total_steps));
  f.write("/pull/time", r.time);
  f.write("/pull/fx", r.fx);
  f.write("/pull/fy", r.fy);
  f.write("/pull/fz", r.fz);
  f.write("/pull/contacts", r.contacts);
  f.write("/pull/theta_sums", std::vector<double>{r.theta_sum, r.theta_sq_sum});
  f.set_attr("/pull", "theta_count", static_cast<std::int64_t>(r.theta_count));
  f.write("/pull/theta_histogram",
          std::vector<std::int64_t>(r.theta_histogram.begin(), r.theta_histogram.end()));
  f.write("/pull/z_histogram", std::vector<std::int64_t>(r.z_histogram.begin(), r.z_histogram.end()));
  f.write("/pull/energy", std::vector<double>{r.work, r.max_overlap, r.energy_start, r.contact_sum});
  f.write_rows("/pull/force_sum", std::vector<Vec3>{r.force_sum});
  f.set_attr("/pull", "snapshots", static_cast<std::int64_t>(r.snapshots.size()));
  write_snapshots(f, "/pull/snapshot_", r.snapshots);
  f.commit();
}

Checkpoint load_checkpoint(const std::string& path, const Bed& bed) {
  const h5::File f = h5::File::open(path);
  check_header(f, path, "granudrag-checkpoint");
  try {
    Checkpoint c;
    const Bed saved = read_bed_body(f);
    if (saved.state.particles.size() != bed.state.particles.size() || saved.box.lx != bed.box.lx ||
        saved.contact.kn != bed.contact.kn || saved.dt != bed.dt)
      throw Error("it belongs to another bed (particle count, box, stiffness or time step differ)");
    c.state = saved.state;
    PullRecord& r = c.record;
    c.identity = f.get_attr_string("/pull", "identity");
    r.samples_per_interval = f.get_attr_int64("/pull", "samples_per_interval");
    if (r.samples_per_interval < 1) throw Error("samples_per_interval < 1 under /pull");
    r.total_steps = f.get_attr_int64("/pull", "total_steps");
    r.time = f.read_doubles("/pull/time");
    r.fx = f.read_doubles("/pull/fx");
    r.fy = f.read_doubles("/pull/fy");
    r.fz = f.read_doubles("/pull/fz");
    r.contacts = f.read_doubles("/pull/contacts");
    const auto theta = f.read_doubles("/pull/theta_sums");
    r.theta_sum = theta.at(0);
    r.theta_sq_sum = theta.at(1);
    r.theta_count = f.get_attr_int64("/pull", "theta_count");
    const auto th = f.read_int64("/pull/theta_histogram");
    r.theta_histogram.assign(th.begin(), th.end());
    const auto zh = f.read_int64("/pull/z_histogram");
    r.z_histogram.assign(zh.begin(), zh.end());
    const auto en = f.read_doubles("/pull/energy");
    r.work = en.at(0);
    r.max_overlap = en.at(1);
    r.energy_start = en.at(2);
    r.contact_sum = en.at(3);
    r.force_sum = f.read_vec3("/pull/force_sum").at(0);
    const std::int64_t ns = f.get_attr_int64("/pull", "snapshots");
    for (std::int64_t k = 0; k < ns; ++k) {
      const std::string g = "/pull/snapshot_" + std::to_string(k);
      Snapshot s;
      s.time = f.get_attr_double(g, "time");
      s.dx = f.read_doubles(g + "/dx");
      s.dz = f.read_doubles(g + "/dz");
      s.vx = f.read_doubles(g + "/vx");
      s.vz = f.read_doubles(g + "/vz");
      r.snapshots.push_back(std::move(s));
    }
    return c;
  } catch (const Error& e) {
    throw Error("checkpoint '" + path + "' cannot be used: " + e.what());
  } catch (const std::out_of_range&) {
    throw Error("checkpoint '" + path + "' is damaged (short arrays under /pull)");
  }
}

void save_run(const std::string& path, const Pull& pull, const std::string& yaml, const std::string& sanity) {
  const PullRecord& r = pull.record();
  const PullResult res = pull.result();
  const Bed& bed = pull.bed();
  h5::File f = h5::File::create(path);
  write_header(f, "granudrag-run", yaml);
  const Particles& p0 = bed.state.particles;
  const double D = 2 * p0.radius[bed.intruder];
  f.set_attr("/run", "D", D);
  f.set_attr("/run", "depth", bed.depth);
  f.set_attr("/run", "speed", pull.spec().speed);
  f.set_attr("/run", "froude", res.froude);
  f.set_attr("/run", "mu", bed.contact.mu);
  f.set_attr("/run", "kn", bed.contact.kn);
  f.set_attr("/run", "gamman", bed.contact.gamman);
  f.set_attr("/run", "dt", bed.dt);
  f.set_attr("/run", "steps", static_cast<std::int64_t>(r.total_steps));
  // Force on the intruder, averaged over each sample interval, as an H5MD time series.
  std::vector<std::int64_t> steps(r.time.size());
  std::vector<Vec3> force(r.time.size());
  for (std::size_t k = 0; k < r.time.size(); ++k) {
    steps[k] = static_cast<std::int64_t>((k + 1) * r.samples_per_interval);
    force[k] = Vec3(r.fx[k], r.fy[k], r.fz[k]);
  }
  f.write("/observables/intruder_force/step", steps);
  f.write("/observables/intruder_force/time", r.time);
  f.write_rows("/observables/intruder_force/value", force);
  f.set_attr("/observables/intruder_force", "meaning",
             std::string("force on the intruder (rho d^3 g), mean over each interval ending at time"));
  f.write("/observables/intruder_contacts/step", steps);
  f.write("/observables/intruder_contacts/time", r.time);
  f.write("/observables/intruder_contacts/value", r.contacts);
  f.write("/observables/cumulative_drag/value", res.cumulative_drag);
  auto scalar = [&](const std::string& name, double value, double error, const std::string& meaning) {
    f.set_attr("/observables/" + name, "value", value);
    f.set_attr("/observables/" + name, "error", error);
    f.set_attr("/observables/" + name, "meaning", meaning);
  };
  scalar("drag", res.drag, res.drag_error,
         "-<F_x> after the transient (rho d^3 g); error by block averaging (Flyvbjerg-Petersen)");
  f.set_attr("/observables/drag", "transient_distance", res.transient_distance);
  f.set_attr("/observables/drag", "transient_samples", static_cast<std::int64_t>(res.transient_samples));
  scalar("coordination", res.coordination, NAN, "n: mean number of grains touching the intruder");
  scalar(
      "theta", res.theta, res.theta_error,
      "mean angle between the intruder velocity and the intruder-to-grain line at contact formation (rad)");
  f.write("/observables/theta/histogram",
          std::vector<std::int64_t>(r.theta_histogram.begin(), r.theta_histogram.end()));
  scalar("bulk_coordination", res.bulk_coordination, NAN,
         "Z of mobile grains with centre within R + shell of the intruder");
  f.set_attr("/observables/bulk_coordination", "shell", pull.spec().shell);
  f.write("/observables/bulk_coordination/distribution", res.z_distribution);
  scalar("kappa", res.kappa, NAN, "(Z/n)(D+d)^2/(2 sqrt(3) d^2), paper Eq. 8");
  write_snapshots(f, "/snapshots/", r.snapshots);
  f.set_attr("/sanity", "report", sanity);
  f.set_attr("/sanity", "max_overlap", r.max_overlap);
  f.set_attr("/sanity", "work", r.work);
  f.commit();
}

void write_bed_xdmf(const std::string& bed_path, std::size_t particles) {
  const std::string name = bed_path.substr(bed_path.find_last_of('/') + 1);
  write_xdmf(bed_path + ".xdmf", name, "all", particles, {"radius"}, {"velocity", "angular_velocity"});
}

}  // namespace granudrag
