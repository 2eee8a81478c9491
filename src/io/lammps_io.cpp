#include "io/lammps_io.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace granudrag {

void write_lammps_data(const std::string& path, const Particles& p, const Box& box, double z_top) {
  std::ostringstream s;
  s << std::setprecision(17);
  s << "LAMMPS data file written by granudrag\n\n"
    << p.size() << " atoms\n3 atom types\n\n"
    << "0 " << box.lx << " xlo xhi\n0 " << box.ly << " ylo yhi\n0 " << z_top << " zlo zhi\n\n"
    << "Atoms # sphere\n\n";
  for (std::size_t i = 0; i < p.size(); ++i) {
    Vec3 x = p.x[i];
    box.wrap(x);
    s << i + 1 << ' ' << static_cast<int>(p.species[i]) + 1 << ' ' << 2 * p.radius[i] << " 1 " << x.x() << ' '
      << x.y() << ' ' << x.z() << '\n';
  }
  s << "\nVelocities\n\n";
  for (std::size_t i = 0; i < p.size(); ++i)
    s << i + 1 << ' ' << p.v[i].x() << ' ' << p.v[i].y() << ' ' << p.v[i].z() << ' ' << p.omega[i].x() << ' '
      << p.omega[i].y() << ' ' << p.omega[i].z() << '\n';
  write_file_atomically(path, s.str());
}

namespace {

// The system both inputs share: box, groups, the paper's contact law between grains and with
// the wall, integration, gravity and the frozen base. The wall acts on `wall_group` ("all" in
// the bench, "mobile" in a pull: frozen grains' forces are zeroed anyway and the intruder never
// reaches the wall, so both are the same physics). `extra_groups` defines groups of the caller.
std::string lammps_system(const std::string& data_file, const ContactParams& c, double skin, double dt,
                          const std::string& extra_groups, const std::string& wall_group) {
  std::ostringstream s;
  s << std::setprecision(17);
  const auto law = [&] {
    std::ostringstream l;
    l << std::setprecision(17) << c.kn << ' ' << c.kt << ' ' << c.gamman << ' ' << c.gammat << ' ' << c.mu
      << " 1";
    return l.str();
  }();
  s << "units lj\natom_style sphere\natom_modify map array\nboundary p p fm\nnewton off\ncomm_modify vel "
       "yes\n"
    << "read_data " << data_file << "\n"
    << "group mobile type 1\ngroup frozen type 2\n"
    << extra_groups << "neighbor " << skin << " bin\nneigh_modify delay 0 every 1 check yes\n"
    << "pair_style gran/hertz/history " << law << "\npair_coeff * *\n"
    << "timestep " << dt << "\n"
    << "fix integrate mobile nve/sphere\n"
    << "fix gravity mobile gravity 1.0 vector 0 0 -1\n"
    << "fix freeze frozen freeze\n"
    << "fix wall " << wall_group << " wall/gran hertz/history " << law << " zplane 0.0 NULL\n";
  return s.str();
}

}  // namespace

void write_lammps_settle_input(const std::string& path, const LammpsRun& run) {
  std::ostringstream s;
  s << "# Written by granudrag: the same system, contact law and steps as `granudrag bench`.\n"
    << lammps_system(run.data_file, run.contact, run.skin, run.dt, "", "all")
    // lj units normalise extensive thermo output by the atom count: energies per grain.
    << "compute ke all ke\ncompute rke all erotate/sphere\n"
    << "thermo_style custom step atoms c_ke c_rke\n"
    << "thermo " << run.thermo_every << "\n"
    << "run " << run.steps << "\n";
  write_file_atomically(path, s.str());
}

void write_lammps_pull_input(const std::string& path, const LammpsPull& run) {
  std::ostringstream s;
  s << std::setprecision(17);
  s << "# Written by granudrag export-lammps: the pull of a granudrag bed in LAMMPS.\n"
    << "# Contact histories start at zero here, as after any read_data (granudrag pull --fresh_start\n"
    << "# does the same for a like-for-like comparison).\n"
    << lammps_system(run.data_file, run.contact, run.skin, run.dt,
                     "group intruder id " + std::to_string(run.intruder_id) + "\n", "mobile")
    << "fix drive intruder move linear " << run.speed << " 0 0\n"
    << "variable fx equal fx[" << run.intruder_id << "]\n"
    << "variable fy equal fy[" << run.intruder_id << "]\n"
    << "variable fz equal fz[" << run.intruder_id << "]\n"
    << "fix force all ave/time 1 " << run.every << ' ' << run.every << " v_fx v_fy v_fz file "
    << run.force_file << " format \" %.17g\"\n"
    << "thermo " << std::max(1L, run.steps / 10) << "\n"
    << "run " << run.steps << "\n";
  write_file_atomically(path, s.str());
}

LammpsData read_lammps_data(const std::string& path, int frozen_type, int intruder_type) {
  std::ifstream in(path);
  if (!in) throw Error("cannot read LAMMPS data file '" + path + "': check the path");
  LammpsData out;
  long natoms = -1, line_no = 0;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool have[3] = {false, false, false};
  std::string line, section;
  struct Atom {
    long id;
    int type;
    double d, density;
    Vec3 x;
  };
  std::vector<Atom> atoms;
  std::map<long, std::pair<Vec3, Vec3>> velocities;
  auto fail = [&](const std::string& why) {
    throw Error("LAMMPS data file '" + path + "', line " + std::to_string(line_no) + ": " + why);
  };
  std::getline(in, line);  // the title line
  ++line_no;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string text = line.substr(0, line.find('#'));
    std::istringstream ls(text);
    std::vector<std::string> w;
    for (std::string t; ls >> t;) w.push_back(t);
    if (w.empty()) continue;
    // Section headers are capitalised words ("Atoms", "Velocities", "Pair Coeffs", ...); only
    // Atoms and Velocities are read, other sections are skipped.
    if (std::isupper(static_cast<unsigned char>(w[0][0]))) {
      section = w[0];
      if (section == "Atoms" && line.find('#') != std::string::npos &&
          line.find("sphere") == std::string::npos)
        fail("the Atoms section is not atom_style sphere ('" + line + "')");
      continue;
    }
    try {
      if (section.empty()) {
        if (w.size() == 2 && w[1] == "atoms") natoms = std::stol(w[0]);
        for (int k = 0; k < 3; ++k) {
          const char* names[3] = {"xlo", "ylo", "zlo"};
          if (w.size() == 4 && w[2] == names[k]) {
            lo[k] = std::stod(w[0]);
            hi[k] = std::stod(w[1]);
            have[k] = true;
          }
        }
      } else if (section == "Atoms") {
        if (w.size() != 7 && w.size() != 10) fail("expected 'id type diameter density x y z [ix iy iz]'");
        Atom a{std::stol(w[0]), std::stoi(w[1]), std::stod(w[2]), std::stod(w[3]),
               Vec3(std::stod(w[4]), std::stod(w[5]), std::stod(w[6]))};
        if (!(a.d > 0)) fail("diameter must be > 0 (a point particle cannot be a grain)");
        if (w.size() == 10)
          a.x += Vec3(std::stol(w[7]) * (hi[0] - lo[0]), std::stol(w[8]) * (hi[1] - lo[1]), 0);
        atoms.push_back(a);
      } else if (section == "Velocities") {
        if (w.size() != 7) fail("expected 'id vx vy vz wx wy wz'");
        velocities[std::stol(w[0])] = {Vec3(std::stod(w[1]), std::stod(w[2]), std::stod(w[3])),
                                       Vec3(std::stod(w[4]), std::stod(w[5]), std::stod(w[6]))};
      }
    } catch (const std::logic_error&) {
      fail("not a number in '" + line + "'");
    }
  }
  if (!have[0] || !have[1] || !have[2]) fail("missing xlo xhi / ylo yhi / zlo zhi");
  if (natoms < 0) fail("missing the 'N atoms' line");
  if (static_cast<long>(atoms.size()) != natoms)
    throw Error("LAMMPS data file '" + path + "' declares " + std::to_string(natoms) + " atoms but lists " +
                std::to_string(atoms.size()) + " (truncated?)");
  if (lo[2] != 0.0)
    throw Error("LAMMPS data file '" + path + "': zlo = " + std::to_string(lo[2]) +
                "; granudrag's wall is at z = 0, shift the data so that zlo = 0");
  std::sort(atoms.begin(), atoms.end(), [](const Atom& a, const Atom& b) { return a.id < b.id; });
  out.box = Box{hi[0] - lo[0], hi[1] - lo[1], true};
  // Intruders last, as granudrag keeps them.
  std::stable_partition(atoms.begin(), atoms.end(), [&](const Atom& a) { return a.type != intruder_type; });
  for (const Atom& a : atoms) {
    if (std::abs(a.density - 1.0) > 1e-12)
      throw Error("LAMMPS data file '" + path + "': atom " + std::to_string(a.id) + " has density " +
                  std::to_string(a.density) + "; granudrag's unit of density is the grains' (1)");
    const Species kind = a.type == intruder_type ? Species::Intruder
                         : a.type == frozen_type ? Species::Frozen
                                                 : Species::Mobile;
    Vec3 x = a.x - Vec3(lo[0], lo[1], 0.0);
    out.box.wrap(x);
    const std::size_t i = out.particles.add(x, 0.5 * a.d, kind);
    const auto v = velocities.find(a.id);
    if (v != velocities.end()) {
      out.particles.v[i] = v->second.first;
      out.particles.omega[i] = v->second.second;
    }
  }
  return out;
}

}  // namespace granudrag
