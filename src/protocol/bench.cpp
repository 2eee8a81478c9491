#include "protocol/bench.hpp"

#include <omp.h>

#include <cstdio>
#include <iostream>
#include <sstream>

#include "contact/verlet_contacts.hpp"
#include "engine/simulation.hpp"
#include "protocol/lattice_bed.hpp"

namespace granudrag {

void run_bench(const BenchOptions& o) {
  LatticeBed bed = fcc_bed(o.grains, o.seed);
  randomize_velocities(bed.particles, o.initial_speed, 0.0, o.seed + 1);
  Settings settings;
  settings.dt = o.dt;
  settings.skin = o.skin;
  if (o.settle_steps > 0) {
    std::fprintf(stderr, "bench: collapsing the lattice for %ld untimed steps\n", o.settle_steps);
    Simulation settle(bed.particles, bed.box, o.contact, settings);
    settle.run(o.settle_steps, true);
    bed.particles = settle.particles();
  }

  std::ostringstream table;
  char line[256];
  std::snprintf(line, sizeof line, "# granudrag bench: %ld grains, box %.2f x %.2f, %ld steps, %s\n",
                o.grains, bed.box.lx, bed.box.ly, o.steps, o.contact.describe().c_str());
  table << line;

  bool exported = false;
  for (int threads : o.threads) {
    omp_set_num_threads(threads);
    Simulation sim(bed.particles, bed.box, o.contact, settings);
    if (o.export_start && !exported) {
      table << o.export_start(bed.particles, bed.box, sim.dt());
      exported = true;
    }
    sim.setup();
    sim.timers().reset();
    const double t0 = omp_get_wtime();
    sim.run(o.steps, true);
    const double wall = omp_get_wtime() - t0;
    const Timers& t = sim.timers();
    const auto& fast = dynamic_cast<const VerletContacts&>(sim.contacts());
    const auto& pairs = fast.list().grain_pairs();
    if (threads == o.threads.front()) {
      const Energy e = sim.energy();
      std::snprintf(line, sizeof line,
                    "# dt = %.6g, skin = %.3g, list entries = %zu, contacts = %ld (%.2f per grain), "
                    "rebuilds = %ld\n# final energy per grain: translational %.6g, rotational %.6g\n",
                    sim.dt(), o.skin, pairs.size(), fast.contact_count(),
                    2.0 * fast.contact_count() / o.grains, fast.list().builds(), e.kinetic / o.grains,
                    e.rotational / o.grains);
      table << line
            << "threads  particle-steps/s  wall[s]  force[s]  neigh[s]  integ[s]  force%  neigh%  integ%\n";
    }
    const double tot = t.total();
    std::snprintf(line, sizeof line, "%7d  %16.4g  %7.2f  %8.2f  %8.2f  %8.2f  %5.1f%%  %5.1f%%  %5.1f%%\n",
                  threads, static_cast<double>(o.grains) * o.steps / wall, wall, t.seconds(Phase::Force),
                  t.seconds(Phase::Neighbor), t.seconds(Phase::Integrate),
                  100 * t.seconds(Phase::Force) / tot, 100 * t.seconds(Phase::Neighbor) / tot,
                  100 * t.seconds(Phase::Integrate) / tot);
    table << line;
    std::cout << table.str() << std::flush;
    table.str("");
    table.clear();
  }
}

}  // namespace granudrag
