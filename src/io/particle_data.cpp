#include "io/particle_data.hpp"

#include "core/error.hpp"

namespace granudrag {

namespace {

const char* kParticles = "/particles/all";

}  // namespace

void write_particle_state(h5::File& f, const Simulation::State& s, double dt) {
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

Simulation::State read_particle_state(const h5::File& f) {
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

std::vector<Snapshot> read_snapshots(const h5::File& f, const std::string& prefix, std::size_t count) {
  std::vector<Snapshot> out;
  for (std::size_t k = 0; k < count; ++k) {
    const std::string g = prefix + std::to_string(k);
    Snapshot s;
    s.time = f.get_attr_double(g, "time");
    s.dx = f.read_doubles(g + "/dx");
    s.dz = f.read_doubles(g + "/dz");
    s.vx = f.read_doubles(g + "/vx");
    s.vz = f.read_doubles(g + "/vz");
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace granudrag
