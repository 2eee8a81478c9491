// granudrag restitution: e(v_n) of a grain hitting the wall, from the engine and from theory.
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "app/command.hpp"
#include "app/output_paths.hpp"
#include "io/atomic_file.hpp"
#include "io/lammps_io.hpp"
#include "protocol/pour.hpp"
#include "protocol/restitution.hpp"

namespace granudrag {

namespace {

std::vector<ParameterSpec> restitution_keys() {
  std::vector<ParameterSpec> keys = {
      output_key("CSV file to write: v_n, e_dem, e_theory"),
      Key::numbers("speeds")
          .unit("sqrt(g d)")
          .default_value("0.01,0.02,0.05,0.1,0.2,0.5,1,2,5,10")
          .above(0)
          .help("normal impact speeds"),
      Key::number("diameter")
          .unit("d")
          .default_value("1")
          .above(0)
          .help("diameter of the grain dropped on the wall"),
  };
  for (const auto& k : contact_keys().specs()) keys.push_back(k);
  keys.push_back(time_step_key());
  keys.push_back(skin_key());
  keys.push_back(threads_key());
  return keys;
}

}  // namespace

int restitution_command(const std::vector<std::string>& args) {
  const auto par = read_parameters(
      "restitution", restitution_keys(),
      "granudrag restitution — coefficient of restitution of a grain hitting the wall (paper Fig. 2):\n"
      "the DEM engine's e(v_n) and the direct integration of the viscoelastic Hertz equation",
      args);
  if (!par) return 0;
  set_threads(*par);
  const ContactParams c = contact_from(*par);
  const double d = par->number("diameter");
  if (par->is_set("dt")) check_time_step(par->number("dt"), c, 0.5 * d);
  const std::string out = par->text("output");
  check_output_dir(out, "output");
  const auto locks = claim_outputs(config_inputs(args), {{"output", out, "text"}});
  std::ostringstream csv;
  csv << std::setprecision(10) << "v_n,e_dem,e_theory\n";
  for (double v : par->numbers("speeds")) {
    const double e_dem = dem_restitution(c, v, d);
    const double e_theory = hertz_collision(c.kn, c.gamman, sphere_mass(0.5 * d), 0.5 * d, v).restitution;
    csv << v << ',' << e_dem << ',' << e_theory << '\n';
    std::printf("v_n = %-6g  e_dem = %.5f  e_theory = %.5f\n", v, e_dem, e_theory);
  }
  write_file_atomically(out, csv.str());
  return 0;
}

}  // namespace granudrag
