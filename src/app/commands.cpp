#include "app/commands.hpp"

#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "core/error.hpp"
#include "core/parameters.hpp"
#include "io/atomic_file.hpp"
#include "io/lammps_io.hpp"
#include "io/run_files.hpp"
#include "protocol/restitution.hpp"

namespace granudrag {

namespace {

using Type = ParameterSpec::Type;
constexpr double inf = ParameterSpec::unbounded;

// The contact law's keys, shared by pour (the bed's law, used by every pull on it).
std::vector<ParameterSpec> contact_specs() {
  return {
      {"kn", Type::Number, "rho d g", "", 0, inf, true,
       "normal stiffness K_n (default 2e8, the paper's); K_t, gamma_n, gamma_t default to the paper's "
       "ratios (K_t/K_n, gamma_t/gamma_n and gamma_n/K_n^0.6 fixed)"},
      {"kt", Type::Number, "rho d g", "", 0, inf, true, "tangential stiffness K_t (default 1.225 K_n)"},
      {"gamman", Type::Number, "sqrt(g/d^3)", "", 0, inf, false,
       "normal damping gamma_n (default 5e4 (K_n/2e8)^0.6)"},
      {"gammat", Type::Number, "sqrt(g/d^3)", "", 0, inf, false,
       "tangential damping gamma_t (default gamma_n)"},
      {"mu", Type::Number, "", "0.5", 0, inf, false, "friction coefficient"},
      {"youngs_modulus", Type::Number, "rho d g", "", 0, inf, true,
       "instead of kn and kt: Young's modulus E (paper Eq. 3)"},
      {"poisson_ratio", Type::Number, "", "0.3", -1, 0.5, true, "Poisson ratio nu with youngs_modulus", false,
       true},
      {"dt", Type::Number, "sqrt(d/g)", "", 0, inf, true,
       "time step (default: Hertz collision time of two 0.9 d grains at 10 sqrt(gd), over 64)"},
      {"skin", Type::Number, "d", "0.2", 0, inf, true, "Verlet-list skin"},
      {"threads", Type::Integer, "", "0", 0, 4096, false, "OpenMP threads (0: OMP_NUM_THREADS or all cores)"},
  };
}

ContactParams contact_from(const Parameters& p) {
  ContactParams c;
  if (p.is_set("youngs_modulus")) {
    if (p.is_set("kt") || p.is_set("kn"))
      throw Error("give either 'youngs_modulus' (with 'poisson_ratio') or 'kn'/'kt', not both");
    c = ContactParams::from_young(p.number("youngs_modulus"), p.number("poisson_ratio"), 0, 0, 0);
    const ContactParams paper;
    c.gamman = paper.gamman * std::pow(c.kn / paper.kn, 0.6);
  } else {
    c = ContactParams{}.with_stiffness(p.is_set("kn") ? p.number("kn") : ContactParams{}.kn);
    if (p.is_set("kt")) c.kt = p.number("kt");
  }
  if (p.is_set("gamman")) c.gamman = p.number("gamman");
  c.gammat = p.is_set("gammat") ? p.number("gammat") : c.gamman;
  c.mu = p.number("mu");
  c.validate();
  return c;
}

void set_threads(const Parameters& p) {
  const long t = p.integer("threads");
  if (t > 0) omp_set_num_threads(static_cast<int>(t));
}

bool wants_help(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

void check_output_dir(const std::string& path, const std::string& key) {
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (!dir.empty() && !std::filesystem::is_directory(dir))
    throw Error("'" + key + "' = " + path + ": directory " + dir.string() +
                " does not exist; create it first");
}

}  // namespace

int pour_command(const std::vector<std::string>& args) {
  std::vector<ParameterSpec> specs = {
      {"output", Type::Text, "", "", -inf, inf, false, "bed file to write (HDF5)", true},
      {"lx", Type::Number, "d", "20", 0, inf, true, "box length along x (periodic; the pull direction)"},
      {"ly", Type::Number, "d", "20", 0, inf, true, "box width along y (periodic)"},
      {"grains", Type::Integer, "", "4000", 1, 1e9, false,
       "number of grains, diameters uniform in [0.9, 1.1] d"},
      {"intruder_diameter", Type::Number, "d", "2", 0, inf, false, "D; 0 for a bed without intruder"},
      {"intruder_x", Type::Number, "d", "", 0, inf, false, "intruder centre x (default lx/2)"},
      {"intruder_y", Type::Number, "d", "", 0, inf, false, "intruder centre y (default ly/2)"},
      {"depth", Type::Number, "d", "", 0, inf, true,
       "requested depth h of the intruder centre below the free surface"},
      {"intruder_z", Type::Number, "d", "", 0, inf, true, "or: height of the intruder centre above the wall"},
      {"packing_estimate", Type::Number, "", "", 0.3, 0.75, false,
       "packing fraction assumed to place the intruder at 'depth' (default: measured, 0.657 at mu = 0 to "
       "0.598 at mu = 0.9)"},
      {"fill_fraction", Type::Number, "", "0.3", 0, 0.35, true,
       "packing fraction of the loose column the grains start in"},
      {"ke_threshold", Type::Number, "rho g d^4", "1e-7", 0, inf, true,
       "settled when the mean kinetic energy per grain is below"},
      {"max_settle_time", Type::Number, "sqrt(d/g)", "100", 0, inf, true,
       "stop settling after this time anyway (recorded)"},
      {"check_interval", Type::Number, "sqrt(d/g)", "0.5", 0, inf, true,
       "time between kinetic-energy checks"},
      {"base_height", Type::Number, "d", "0.6", 0, inf, false,
       "grains with centre below are frozen into the rough base"},
      {"seed", Type::Integer, "", "1", 0, 9e18, false, "random seed of the placement"},
      {"quiet", Type::Flag, "", "false", -inf, inf, false, "no progress lines on stderr"},
  };
  const auto contact = contact_specs();
  specs.insert(specs.end(), contact.begin(), contact.end());
  Parameters par("pour", specs);
  if (wants_help(args)) {
    std::cout << "granudrag pour — pour and settle a bed around a fixed intruder\n\n"
                 "  granudrag pour --output bed.h5 [--config pour.yaml] [--key value ...]\n\n"
              << par.help_text();
    return 0;
  }
  par.apply_cli(args);
  par.validate();
  set_threads(par);
  PourSpec s;
  s.lx = par.number("lx");
  s.ly = par.number("ly");
  s.grains = par.integer("grains");
  s.intruder_diameter = par.number("intruder_diameter");
  s.intruder_x = par.is_set("intruder_x") ? par.number("intruder_x") : 0.5 * s.lx;
  s.intruder_y = par.is_set("intruder_y") ? par.number("intruder_y") : 0.5 * s.ly;
  if (par.is_set("depth")) s.depth = par.number("depth");
  if (par.is_set("intruder_z")) s.intruder_z = par.number("intruder_z");
  if (s.intruder_diameter > 0 && std::isnan(s.depth) && std::isnan(s.intruder_z))
    throw Error("give 'depth' (below the free surface) or 'intruder_z' for the intruder");
  if (par.is_set("packing_estimate")) s.packing_estimate = par.number("packing_estimate");
  s.fill_fraction = par.number("fill_fraction");
  s.contact = contact_from(par);
  if (par.is_set("dt")) s.dt = par.number("dt");
  s.skin = par.number("skin");
  s.ke_threshold = par.number("ke_threshold");
  s.max_settle_time = par.number("max_settle_time");
  s.check_interval = par.number("check_interval");
  s.base_height = par.number("base_height");
  s.seed = static_cast<std::uint64_t>(par.integer("seed"));
  const std::string out = par.text("output");
  check_output_dir(out, "output");

  const double t0 = omp_get_wtime();
  const Bed bed = pour(s, !par.flag("quiet"));
  save_bed(out, bed, par);
  write_bed_xdmf(out, bed.state.particles.size());
  std::printf("bed: %s\n  grains %ld (%zu frozen in the base), box %g x %g, dt %.4g\n", out.c_str(), s.grains,
              bed.state.particles.count(Species::Frozen), s.lx, s.ly, bed.dt);
  std::printf("  settling stopped by %s at t = %.2f sqrt(d/g), kinetic energy per grain %.3g\n",
              bed.stop_reason.c_str(), bed.settle_time, bed.kinetic_energy);
  std::printf("  surface height %.3f d (half bulk packing), bulk packing fraction %.4f\n", bed.surface_height,
              bed.profile.bulk_packing_fraction);
  if (bed.intruder >= 0)
    std::printf(
        "  intruder D = %g at depth h = %.3f d (requested %s)\n", s.intruder_diameter, bed.depth,
        std::isnan(bed.requested_depth) ? "by intruder_z" : std::to_string(bed.requested_depth).c_str());
  std::printf("  wall time %.1f s\n%s", omp_get_wtime() - t0, bed.sanity.c_str());
  return 0;
}

int pull_command(const std::vector<std::string>& args) {
  std::vector<ParameterSpec> specs = {
      {"bed", Type::Text, "", "", -inf, inf, false, "bed file from granudrag pour", true},
      {"output", Type::Text, "", "", -inf, inf, false, "run file to write (HDF5)", true},
      {"speed", Type::Number, "sqrt(g d)", "", 0, inf, true, "pulling speed V along +x (default 1)"},
      {"froude", Type::Number, "", "", 0, inf, true,
       "or: the Froude number 2V sqrt(2D/g)/(D+d), paper Eq. 4"},
      {"distance", Type::Number, "d", "0", 0, inf, false, "travel; 0: one box length (as in the paper)"},
      {"sample_interval", Type::Number, "sqrt(d/g)", "0.02", 0, inf, true,
       "forces are averaged over each interval"},
      {"transient", Type::Number, "d", "-1", -inf, inf, false,
       "travel discarded before averaging; < 0: min(D + d, distance/4)"},
      {"shell", Type::Number, "d", "2", 0, inf, true,
       "Z is measured for grains with centre within D/2 + shell"},
      {"snapshots", Type::Integer, "", "3", 0, 1000, false,
       "velocity snapshots of the slab through the intruder"},
      {"slab_half_width", Type::Number, "d", "0.5", 0, inf, true, "half width of that slab in y"},
      {"checkpoint_interval", Type::Number, "sqrt(d/g)", "0", 0, inf, false,
       "simulated time between checkpoints (<output>.checkpoint.h5); 0: every tenth of the pull"},
      {"resume", Type::Flag, "", "false", -inf, inf, false,
       "continue from <output>.checkpoint.h5 if it exists"},
      {"skin", Type::Number, "d", "0.2", 0, inf, true, "Verlet-list skin"},
      {"fresh_start", Type::Flag, "", "false", -inf, inf, false,
       "drop the bed's contact histories and recompute forces first, as LAMMPS does after read_data"},
      {"threads", Type::Integer, "", "0", 0, 4096, false, "OpenMP threads (0: OMP_NUM_THREADS or all cores)"},
      {"quiet", Type::Flag, "", "false", -inf, inf, false, "no progress lines on stderr"},
  };
  Parameters par("pull", specs);
  if (wants_help(args)) {
    std::cout
        << "granudrag pull — pull the intruder of a bed at constant speed and record the drag\n\n"
           "  granudrag pull --bed bed.h5 --output run.h5 [--speed V | --froude Fr] [--key value ...]\n\n"
        << par.help_text();
    return 0;
  }
  par.apply_cli(args);
  par.validate();
  set_threads(par);
  const std::string bed_path = par.text("bed"), out = par.text("output");
  check_output_dir(out, "output");
  ParameterRecord bed_parameters;
  const Bed bed = load_bed(bed_path, &bed_parameters);
  if (bed.intruder < 0) throw Error("bed '" + bed_path + "' has no intruder to pull");
  PullSpec spec;
  const double D = 2 * bed.state.particles.radius[bed.intruder];
  if (par.is_set("speed") && par.is_set("froude")) throw Error("give either 'speed' or 'froude', not both");
  spec.speed = par.is_set("speed") ? par.number("speed") : 1.0;
  if (par.is_set("froude")) spec.speed = par.number("froude") / froude_number(1.0, D);
  spec.distance = par.number("distance");
  spec.sample_interval = par.number("sample_interval");
  spec.transient = par.number("transient");
  spec.shell = par.number("shell");
  spec.snapshots = static_cast<int>(par.integer("snapshots"));
  spec.slab_half_width = par.number("slab_half_width");
  spec.skin = par.number("skin");
  spec.fresh_start = par.flag("fresh_start");
  {
    const double distance = spec.distance > 0 ? spec.distance : bed.box.lx;
    const double total_time = distance / spec.speed;
    const double interval =
        par.number("checkpoint_interval") > 0 ? par.number("checkpoint_interval") : total_time / 10;
    spec.checkpoint_every = std::max(1L, std::lround(interval / bed.dt));
  }
  const std::string checkpoint = out + ".checkpoint.h5";

  const double t0 = omp_get_wtime();
  auto save = [&](const Pull& p) { save_checkpoint(checkpoint, p, par, bed_parameters); };
  std::unique_ptr<Pull> pull;
  if (par.flag("resume") && std::filesystem::exists(checkpoint)) {
    // A resumed pull must match every option but the run controls, and the bed itself.
    Checkpoint c = load_checkpoint(checkpoint, bed, par, {"resume", "quiet", "threads"});
    pull = std::make_unique<Pull>(bed, spec, c.state, std::move(c.record));
    std::fprintf(stderr, "pull: resuming from %s at step %ld\n", checkpoint.c_str(),
                 pull->simulation().steps_done());
  } else {
    pull = std::make_unique<Pull>(bed, spec);
  }
  pull->run(!par.flag("quiet"), save);
  const double wall = omp_get_wtime() - t0;
  const std::string sanity = pull->sanity_report(wall);
  save_run(out, *pull, par, bed_parameters, sanity);
  std::filesystem::remove(checkpoint);
  const PullResult r = pull->result();
  std::printf("run: %s\n  D = %g, depth %.3f d, V = %.4g sqrt(gd), Fr = %.4g, mu = %g, kn = %g\n",
              out.c_str(), D, bed.depth, spec.speed, r.froude, bed.contact.mu, bed.contact.kn);
  std::printf("  drag = %.5g +- %.2g rho d^3 g (transient %.3g d discarded: %ld of %zu samples)\n", r.drag,
              r.drag_error, r.transient_distance, r.transient_samples, pull->record().fx.size());
  std::printf("  n = %.3f, theta = %.4f +- %.2g rad, Z = %.3f, kappa = %.4f\n", r.coordination, r.theta,
              r.theta_error, r.bulk_coordination, r.kappa);
  std::printf("%s", sanity.c_str());
  return 0;
}

int export_lammps_command(const std::vector<std::string>& args) {
  std::vector<ParameterSpec> specs = {
      {"bed", Type::Text, "", "", -inf, inf, false, "bed file from granudrag pour", true},
      {"output", Type::Text, "", "", -inf, inf, false, "prefix: writes PREFIX.data and PREFIX.in", true},
      {"speed", Type::Number, "sqrt(g d)", "1", 0, inf, true, "pulling speed V along +x"},
      {"distance", Type::Number, "d", "0", 0, inf, false, "travel; 0: one box length"},
      {"steps", Type::Integer, "", "0", 0, 1e15, false, "or: number of steps (overrides distance)"},
      {"every", Type::Integer, "", "1", 1, 1e15, false, "steps per line of the force file (averaged)"},
      {"skin", Type::Number, "d", "0.2", 0, inf, true, "Verlet-list skin"},
  };
  Parameters par("export-lammps", specs);
  if (wants_help(args)) {
    std::cout
        << "granudrag export-lammps — write a bed as a LAMMPS data file plus an input script that runs\n"
           "the same pull with gran/hertz/history (run it as: cd DIR && lmp -in PREFIX.in)\n\n"
        << par.help_text();
    return 0;
  }
  par.apply_cli(args);
  par.validate();
  const Bed bed = load_bed(par.text("bed"));
  if (bed.intruder < 0) throw Error("bed '" + par.text("bed") + "' has no intruder to pull");
  const std::string prefix = par.text("output");
  check_output_dir(prefix, "output");
  Particles p = bed.state.particles;
  const double speed = par.number("speed");
  p.v[bed.intruder] = Vec3(speed, 0, 0);
  double ztop = 0;
  for (const Vec3& x : p.x) ztop = std::max(ztop, x.z());
  write_lammps_data(prefix + ".data", p, bed.box, ztop + 2.0 * p.max_radius(Species::Intruder) + 2.0);
  LammpsPull run;
  const std::string base = prefix.substr(prefix.find_last_of('/') + 1);
  run.data_file = base + ".data";
  run.force_file = base + ".force.txt";
  run.contact = bed.contact;
  run.dt = bed.dt;
  run.skin = par.number("skin");
  run.speed = speed;
  const double distance = par.number("distance") > 0 ? par.number("distance") : bed.box.lx;
  run.steps =
      par.integer("steps") > 0 ? par.integer("steps") : std::lround(std::ceil(distance / (speed * bed.dt)));
  run.every = par.integer("every");
  run.intruder_id = bed.intruder + 1;
  write_lammps_pull_input(prefix + ".in", run);
  std::printf("wrote %s.data and %s.in (%ld steps; force on the intruder to %s)\n", prefix.c_str(),
              prefix.c_str(), run.steps, run.force_file.c_str());
  return 0;
}

int import_lammps_command(const std::vector<std::string>& args) {
  std::vector<ParameterSpec> specs = {
      {"data", Type::Text, "", "", -inf, inf, false, "LAMMPS data file (atom_style sphere, density 1)", true},
      {"output", Type::Text, "", "", -inf, inf, false, "bed file to write (HDF5)", true},
      {"frozen_type", Type::Integer, "", "2", 0, 1e9, false, "atom type of the frozen base grains (0: none)"},
      {"intruder_type", Type::Integer, "", "3", 0, 1e9, false, "atom type of the intruder (0: none)"},
  };
  const auto contact = contact_specs();
  specs.insert(specs.end(), contact.begin(), contact.end());
  Parameters par("import-lammps", specs);
  if (wants_help(args)) {
    std::cout << "granudrag import-lammps — turn a LAMMPS data file into a granudrag bed (contact histories\n"
                 "start at zero: data files do not carry them)\n\n"
              << par.help_text();
    return 0;
  }
  par.apply_cli(args);
  par.validate();
  const std::string out = par.text("output");
  check_output_dir(out, "output");
  const LammpsData data = read_lammps_data(par.text("data"), static_cast<int>(par.integer("frozen_type")),
                                           static_cast<int>(par.integer("intruder_type")));
  Bed bed;
  bed.box = data.box;
  bed.contact = contact_from(par);
  const double rmin =
      std::min(data.particles.min_radius(Species::Mobile), data.particles.min_radius(Species::Frozen));
  bed.dt =
      par.is_set("dt") ? par.number("dt") : default_time_step(bed.contact, std::isfinite(rmin) ? rmin : 0.5);
  check_time_step(bed.dt, bed.contact, std::isfinite(rmin) ? rmin : 0.5);
  if (data.particles.count(Species::Intruder) > 1) throw Error("more than one intruder in the data file");
  bed.intruder =
      data.particles.count(Species::Intruder) == 1 ? static_cast<int>(data.particles.size()) - 1 : -1;
  // Forces of the imported state, with no history, as the first step of a pull needs them.
  Settings settings;
  settings.dt = bed.dt;
  settings.skin = par.number("skin");
  Simulation sim(data.particles, bed.box, bed.contact, settings);
  sim.setup();
  bed.state = sim.state();
  bed.profile = measure_bed(bed.state.particles, bed.box);
  bed.surface_height = bed.profile.surface_height;
  if (bed.intruder >= 0) bed.depth = bed.surface_height - bed.state.particles.x[bed.intruder].z();
  bed.stop_reason = "imported";
  save_bed(out, bed, par);
  write_bed_xdmf(out, bed.state.particles.size());
  std::printf("bed: %s from %s\n  %zu particles (%zu frozen, %zu intruder), surface %.3f d, depth %.3f d\n",
              out.c_str(), par.text("data").c_str(), bed.state.particles.size(),
              bed.state.particles.count(Species::Frozen), bed.state.particles.count(Species::Intruder),
              bed.surface_height, bed.depth);
  return 0;
}

int restitution_command(const std::vector<std::string>& args) {
  std::vector<ParameterSpec> specs = {
      {"output", Type::Text, "", "", -inf, inf, false, "CSV file to write: v_n, e_dem, e_theory", true},
      {"speeds", Type::NumberList, "sqrt(g d)", "0.01,0.02,0.05,0.1,0.2,0.5,1,2,5,10", 0, inf, true,
       "normal impact speeds"},
      {"diameter", Type::Number, "d", "1", 0, inf, true, "diameter of the grain dropped on the wall"},
  };
  const auto contact = contact_specs();
  specs.insert(specs.end(), contact.begin(), contact.end());
  Parameters par("restitution", specs);
  if (wants_help(args)) {
    std::cout
        << "granudrag restitution — coefficient of restitution of a grain hitting the wall (paper Fig. 2):\n"
           "the DEM engine's e(v_n) and the direct integration of the viscoelastic Hertz equation\n\n"
        << par.help_text();
    return 0;
  }
  par.apply_cli(args);
  par.validate();
  set_threads(par);
  const ContactParams c = contact_from(par);
  const double d = par.number("diameter");
  if (par.is_set("dt")) check_time_step(par.number("dt"), c, 0.5 * d);
  const std::string out = par.text("output");
  check_output_dir(out, "output");
  std::ostringstream csv;
  csv << std::setprecision(10) << "v_n,e_dem,e_theory\n";
  for (double v : par.numbers("speeds")) {
    const double e_dem = dem_restitution(c, v, d);
    const double e_theory = hertz_collision(c.kn, c.gamman, sphere_mass(0.5 * d), 0.5 * d, v).restitution;
    csv << v << ',' << e_dem << ',' << e_theory << '\n';
    std::printf("v_n = %-6g  e_dem = %.5f  e_theory = %.5f\n", v, e_dem, e_theory);
  }
  write_file_atomically(out, csv.str());
  return 0;
}

}  // namespace granudrag
