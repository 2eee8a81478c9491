#include "lammps_io.hpp"

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "error.hpp"

namespace granudrag {

void write_file_atomically(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw Error("cannot write '" + tmp + "': check that its directory exists and is writable");
    out << content;
    out.flush();
    if (!out) throw Error("writing '" + tmp + "' failed (disk full?)");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw Error("cannot rename '" + tmp + "' to '" + path + "'");
}

void write_lammps_data(const std::string& path, const Particles& p, const Box& box,
                       double z_top) {
  std::ostringstream s;
  s << std::setprecision(17);
  s << "LAMMPS data file written by granudrag\n\n"
    << p.size() << " atoms\n3 atom types\n\n"
    << "0 " << box.lx << " xlo xhi\n0 " << box.ly << " ylo yhi\n0 " << z_top << " zlo zhi\n\n"
    << "Atoms # sphere\n\n";
  for (std::size_t i = 0; i < p.size(); ++i) {
    Vec3 x = p.x[i];
    box.wrap(x);
    s << i + 1 << ' ' << static_cast<int>(p.kind[i]) + 1 << ' ' << 2 * p.radius[i] << " 1 "
      << x.x() << ' ' << x.y() << ' ' << x.z() << '\n';
  }
  s << "\nVelocities\n\n";
  for (std::size_t i = 0; i < p.size(); ++i)
    s << i + 1 << ' ' << p.v[i].x() << ' ' << p.v[i].y() << ' ' << p.v[i].z() << ' '
      << p.omega[i].x() << ' ' << p.omega[i].y() << ' ' << p.omega[i].z() << '\n';
  write_file_atomically(path, s.str());
}

void write_lammps_settle_input(const std::string& path, const LammpsRun& run) {
  const ContactParams& c = run.contact;
  std::ostringstream s;
  s << std::setprecision(17);
  s << "# Written by granudrag: the same system, contact law and steps as `granudrag bench`.\n"
    << "units lj\natom_style sphere\nboundary p p fm\nnewton off\ncomm_modify vel yes\n"
    << "read_data " << run.data_file << "\n"
    << "group mobile type 1\ngroup frozen type 2\n"
    << "neighbor " << run.skin << " bin\nneigh_modify delay 0 every 1 check yes\n"
    << "pair_style gran/hertz/history " << c.kn << ' ' << c.kt << ' ' << c.gamman << ' '
    << c.gammat << ' ' << c.mu << " 1\npair_coeff * *\n"
    << "timestep " << run.dt << "\n"
    << "fix integrate mobile nve/sphere\n"
    << "fix gravity mobile gravity 1.0 vector 0 0 -1\n"
    << "fix freeze frozen freeze\n"
    << "fix wall all wall/gran hertz/history " << c.kn << ' ' << c.kt << ' ' << c.gamman << ' '
    << c.gammat << ' ' << c.mu << " 1 zplane 0.0 NULL\n"
    // lj units normalise extensive thermo output by the atom count: energies per grain.
    << "compute ke all ke\ncompute rke all erotate/sphere\n"
    << "thermo_style custom step atoms c_ke c_rke\n"
    << "thermo " << run.thermo_every << "\n"
    << "run " << run.steps << "\n";
  write_file_atomically(path, s.str());
}

}  // namespace granudrag
