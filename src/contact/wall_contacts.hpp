#pragma once
// Contacts of grains with the flat wall at z = 0 (LAMMPS `fix wall/gran hertz/history zplane`):
// the same law with R_eff = R_i and m_eff = m_i, one tangential spring per grain.
#include <cstdint>
#include <utility>
#include <vector>

#include "contact/contact_params.hpp"
#include "core/particles.hpp"

namespace granudrag {

class WallContacts {
 public:
  // Restricts the next evaluations to the mobile grains within `skin` of touching the wall, as
  // the neighbour lists are built (those cover every body that moves under half a skin until
  // they are rebuilt, and so does this). Until it is called, every grain is checked.
  void select(const Particles& p, double skin);
  void accumulate(Particles& p, const ContactParams& c, double dt, bool update_history);
  // accumulate() inside the caller's parallel region: prepare() before it, then each thread
  // evaluates the grains among bodies first .. last - 1 (a grain's wall force touches that
  // grain alone: any split gives the same bits).
  void prepare(const Particles& p);
  void accumulate_range(Particles& p, const ContactParams& c, double dt, bool update_history, long first,
                        long last);
  double elastic_energy(const Particles& p, const ContactParams& c) const;
  // Sets exposed[i] = 1 for every grain the next evaluations check (all, before select()).
  void mark_near(std::vector<std::uint8_t>& exposed) const;
  const std::vector<Vec3>& shear() const { return shear_; }
  void restore_shear(std::vector<Vec3> shear) { shear_ = std::move(shear); }

 private:
  std::vector<Vec3> shear_;  // per grain; zero for every grain not touching the wall
  std::vector<int> near_;    // the grains select() found within reach
  bool selected_ = false;
  void evaluate(Particles& p, long i, const ContactParams& c, double dt, bool update_history);
};

}  // namespace granudrag
